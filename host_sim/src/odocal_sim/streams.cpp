// odocal-sim: the console's streams, scripted input, pacing and the stop signal.

#include <poll.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstring>
#include <thread>

#include "sim_app.hpp"

namespace odocal::sim_app {
namespace {

std::atomic<bool> stop_flag{false};
std::atomic<bool> reset_flag{false};

void on_signal(int) {
  stop_flag.store(true);
}

void on_reset_signal(int) {
  reset_flag.store(true);
}

}  // namespace

bool stop_requested() {
  return stop_flag.load();
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  struct sigaction reset {};
  reset.sa_handler = on_reset_signal;
  sigaction(SIGUSR1, &reset, nullptr);
  // SIGUSR2: the adapter unplugged. The program ends and its pty with it: the host's end of the
  // line hangs up.
  sigaction(SIGUSR2, &action, nullptr);
}

bool take_reset_request() {
  return reset_flag.exchange(false);
}

std::size_t ScriptedStream::do_read(std::uint8_t* out, std::size_t capacity) {
  const std::size_t n = std::min(capacity, pending_.size() - taken_);
  std::memcpy(out, pending_.data() + taken_, n);
  taken_ += n;
  if (taken_ == pending_.size()) {
    pending_.clear();
    taken_ = 0u;
  }
  return n;
}

std::size_t LineCountingStream::do_read(std::uint8_t* out, std::size_t /*capacity*/) {
  if (!accepting_) {
    return 0u;
  }
  // One line at a time: the bytes after a line end stay in the pty until its quantum is over.
  const std::size_t n = inner_.read(out, 1u);
  for (std::size_t i = 0; i < n; ++i) {
    if (out[i] == '\r' || (out[i] == '\n' && !after_cr_)) {
      ++lines_;
      accepting_ = false;
    }
    after_cr_ = out[i] == '\r';
  }
  return n;
}

bool LineReader::next(std::string& piece, bool& line_end) {
  for (;;) {
    if (begin_ < end_) {
      std::size_t stop = begin_;
      while (stop < end_ && chunk_[stop] != '\r' && chunk_[stop] != '\n') {
        ++stop;
      }
      line_end = stop < end_;
      if (line_end) {
        // A CRLF split over two reads gives a lone LF next: the console takes it as the end of
        // the same line.
        ++stop;
      }
      piece.assign(reinterpret_cast<const char*>(chunk_ + begin_), stop - begin_);
      begin_ = stop;
      in_line_ = !line_end;
      return true;
    }
    if (stream_.end_of_input() || stop_requested()) {
      if (!in_line_) {
        return false;
      }
      piece = "\n";
      line_end = true;
      in_line_ = false;
      return true;
    }
    begin_ = 0u;
    end_ = stream_.read(chunk_, sizeof chunk_);
    if (end_ == 0u && !stream_.end_of_input()) {
      pollfd wait{stream_.input_fd(), POLLIN, 0};
      static_cast<void>(::poll(&wait, 1, 20));
    }
  }
}

void Pacer::wait_for(double simulated_s) const {
  if (!(speed_ > 0.0)) {
    return;
  }
  const double due_wall_s = (simulated_s - base_s_) / speed_;
  const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(due_wall_s));
  if (due > std::chrono::steady_clock::now()) {
    std::this_thread::sleep_until(due);
  }
}

double CorruptingStream::uniform() {
  // splitmix64: a small, seedable stream of its own.
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

std::size_t CorruptingStream::do_write(const std::uint8_t* data, std::size_t size) {
  std::size_t taken = 0;
  while (taken < size) {
    if (!decided_) {
      const double u = uniform();
      fate_ = u < 0.5 * rate_ ? -1 : u < rate_ ? 1 + static_cast<int>(uniform() * 8.0) % 8 : 0;
      decided_ = true;
    }
    if (fate_ < 0) {
      decided_ = false;  // lost on the line
      ++taken;
      continue;
    }
    const std::uint8_t byte =
        fate_ == 0 ? data[taken] : static_cast<std::uint8_t>(data[taken] ^ (1u << (fate_ - 1)));
    if (inner_.write(&byte, 1u) != 1u) {
      break;  // the line is full: this byte's fate waits for the next write
    }
    decided_ = false;
    ++taken;
  }
  return taken;
}

bool busy(const drive::LoopStatus& status, const console::Console& console) {
  return status.mode == drive::Mode::path || status.mode == drive::Mode::drive ||
         status.trial_open || console.selftest_running();
}

}  // namespace odocal::sim_app

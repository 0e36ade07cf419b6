#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "odocal/posix/fd_byte_stream.hpp"
#include "odocal/posix/file_block_store.hpp"

namespace odocal::posix {
namespace {

std::string temp_path(const char* name) {
  const char* dir = std::getenv("TMPDIR");
  std::string path = std::string(dir != nullptr ? dir : "/tmp") + "/odocal_posix_" +
                     std::to_string(::getpid()) + "_" + name;
  std::remove(path.c_str());
  return path;
}

std::size_t file_size(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 ? static_cast<std::size_t>(info.st_size) : 0u;
}

TEST(FileBlockStore, MissingFileIsAnErasedDevice) {
  const std::string path = temp_path("missing.bin");
  FileBlockStore store(path, 1024, 2, 4);
  std::string error;
  ASSERT_TRUE(store.open(error)) << error;
  std::array<std::uint8_t, 16> bytes{};
  ASSERT_EQ(store.read(1000, bytes.data(), bytes.size()), hal::StoreStatus::ok);
  for (auto b : bytes)
    EXPECT_EQ(b, 0xFF);
  EXPECT_EQ(file_size(path), 0u);  // nothing written yet
}

TEST(FileBlockStore, AnEmptyFileIsAnErasedDeviceThatCanBeProgrammed) {
  const std::string path = temp_path("empty.bin");
  { std::ofstream create(path); }  // as `mktemp` or `: > store.bin` leave it
  ASSERT_EQ(file_size(path), 0u);
  FileBlockStore store(path, 1024, 2, 4);
  std::string error;
  ASSERT_TRUE(store.open(error)) << error;
  std::array<std::uint8_t, 4> bytes{};
  ASSERT_EQ(store.read(0, bytes.data(), bytes.size()), hal::StoreStatus::ok);
  for (auto b : bytes)
    EXPECT_EQ(b, 0xFF);
  const std::array<std::uint8_t, 4> data{1, 2, 3, 4};
  ASSERT_EQ(store.program(8, data.data(), data.size()), hal::StoreStatus::ok);
  EXPECT_EQ(file_size(path), 2048u);  // now a full image
  std::remove(path.c_str());
}

TEST(FileBlockStore, KeepsFlashRulesAndPersistsAcrossReopen) {
  const std::string path = temp_path("rules.bin");
  {
    FileBlockStore store(path, 1024, 2, 4);
    std::string error;
    ASSERT_TRUE(store.open(error)) << error;
    const std::uint8_t data[8] = {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xF0};
    ASSERT_EQ(store.program(1024, data, 8), hal::StoreStatus::ok);
    EXPECT_EQ(file_size(path), 2048u);
    // Only 1 -> 0: programming a 1 over a 0 is refused and changes nothing.
    const std::uint8_t ones[4] = {0xFF, 0xFF, 0xFF, 0xFE};
    EXPECT_EQ(store.program(1024, ones, 4), hal::StoreStatus::not_erased);
    // Alignment and bounds.
    EXPECT_EQ(store.program(1026, data, 4), hal::StoreStatus::out_of_range);
    EXPECT_EQ(store.program(1024, data, 3), hal::StoreStatus::out_of_range);
    EXPECT_EQ(store.program(2048, data, 4), hal::StoreStatus::out_of_range);
    EXPECT_EQ(store.erase(2), hal::StoreStatus::out_of_range);
    // Clearing more bits of an already programmed word is allowed (as on NOR flash).
    const std::uint8_t fewer[4] = {0x10, 0x34, 0x56, 0x78};
    EXPECT_EQ(store.program(1024, fewer, 4), hal::StoreStatus::ok);
    EXPECT_EQ(store.commits(), 2u);
  }
  FileBlockStore reopened(path, 1024, 2, 4);
  std::string error;
  ASSERT_TRUE(reopened.open(error)) << error;
  std::array<std::uint8_t, 8> back{};
  ASSERT_EQ(reopened.read(1024, back.data(), back.size()), hal::StoreStatus::ok);
  const std::uint8_t expected[8] = {0x10, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xF0};
  EXPECT_EQ(std::memcmp(back.data(), expected, 8), 0);
  ASSERT_EQ(reopened.erase(1), hal::StoreStatus::ok);
  ASSERT_EQ(reopened.read(1024, back.data(), back.size()), hal::StoreStatus::ok);
  for (auto b : back)
    EXPECT_EQ(b, 0xFF);
  std::ifstream temporary(path + ".tmp");
  EXPECT_FALSE(temporary.good()) << "the temporary file must be renamed away";
  std::remove(path.c_str());
}

TEST(FileBlockStore, RefusesAFileOfTheWrongSizeAndLeavesItAlone) {
  const std::string path = temp_path("wrong.bin");
  {
    std::ofstream file(path);
    file << "not a store";
  }
  FileBlockStore store(path, 1024, 2, 4);
  std::string error;
  EXPECT_FALSE(store.open(error));
  EXPECT_NE(error.find(path), std::string::npos);
  std::uint8_t byte = 0;
  EXPECT_EQ(store.read(0, &byte, 1), hal::StoreStatus::device_error);
  EXPECT_EQ(store.erase(0), hal::StoreStatus::device_error);
  EXPECT_EQ(file_size(path), 11u);
  std::remove(path.c_str());
}

TEST(FileBlockStore, AnOperationThatCannotReachTheDiskFailsAndChangesNothing) {
  const std::string path = temp_path("blocked.bin");
  FileBlockStore store(path, 1024, 2, 4);
  std::string error;
  ASSERT_TRUE(store.open(error));
  const std::uint8_t data[4] = {0, 0, 0, 0};
  ASSERT_EQ(store.program(0, data, 4), hal::StoreStatus::ok);
  // A directory where the temporary file must go: the write fails (even for root).
  ASSERT_EQ(::mkdir((path + ".tmp").c_str(), 0755), 0);
  EXPECT_EQ(store.erase(0), hal::StoreStatus::device_error);
  std::array<std::uint8_t, 4> back{};
  ASSERT_EQ(store.read(0, back.data(), 4), hal::StoreStatus::ok);
  EXPECT_EQ(back[0], 0u);  // the failed erase took effect neither in memory nor on disk
  FileBlockStore reopened(path, 1024, 2, 4);
  ASSERT_TRUE(reopened.open(error));
  ASSERT_EQ(reopened.read(0, back.data(), 4), hal::StoreStatus::ok);
  EXPECT_EQ(back[0], 0u);
  ::rmdir((path + ".tmp").c_str());
  EXPECT_EQ(store.erase(0), hal::StoreStatus::ok);
  std::remove(path.c_str());
}

TEST(FdByteStream, ReadNeverBlocksAndSeesEndOfInput) {
  int in[2];
  int out[2];
  ASSERT_EQ(::pipe(in), 0);
  ASSERT_EQ(::pipe(out), 0);
  {
    FdByteStream stream(in[0], out[1]);
    std::array<std::uint8_t, 16> buffer{};
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(stream.read(buffer.data(), buffer.size()), 0u);  // empty: returns at once
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
    EXPECT_FALSE(stream.end_of_input());
    ASSERT_EQ(::write(in[1], "get c_l\n", 8), 8);
    EXPECT_EQ(stream.read(buffer.data(), buffer.size()), 8u);
    EXPECT_EQ(std::memcmp(buffer.data(), "get c_l\n", 8), 0);
    const std::uint8_t reply[] = {'o', 'k', '\n'};
    EXPECT_EQ(stream.write(reply, 3), 3u);
    char got[3];
    ASSERT_EQ(::read(out[0], got, 3), 3);
    EXPECT_EQ(std::memcmp(got, "ok\n", 3), 0);
    ::close(in[1]);
    EXPECT_EQ(stream.read(buffer.data(), buffer.size()), 0u);
    EXPECT_TRUE(stream.end_of_input());
  }
  // The caller's descriptors keep their blocking mode.
  EXPECT_EQ(::fcntl(in[0], F_GETFL) & O_NONBLOCK, 0);
  EXPECT_EQ(::fcntl(out[1], F_GETFL) & O_NONBLOCK, 0);
  ::close(in[0]);
  ::close(out[0]);
  ::close(out[1]);
}

TEST(FdByteStream, WriteToAFullPipeReturnsShortInsteadOfBlocking) {
  int out[2];
  ASSERT_EQ(::pipe(out), 0);
  FdByteStream stream(-1, out[1]);
  std::vector<std::uint8_t> chunk(4096, 'x');
  std::size_t total = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 1000; ++i) {
    const std::size_t n = stream.write(chunk.data(), chunk.size());
    total += n;
    if (n < chunk.size())
      break;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_LT(total, 1000u * 4096u);  // the pipe filled and the stream said so
  EXPECT_EQ(stream.write(chunk.data(), chunk.size()), 0u);
  EXPECT_FALSE(stream.output_broken());
  ::close(out[0]);
  ::close(out[1]);
}

TEST(PtyByteStream, ATerminalOnTheSlaveTalksToTheConsole) {
  PtyByteStream pty;
  std::string error;
  ASSERT_TRUE(pty.open(error)) << error;
  ASSERT_EQ(pty.slave_name().rfind("/dev/pts/", 0), 0u) << pty.slave_name();
  std::array<std::uint8_t, 64> buffer{};
  EXPECT_EQ(pty.read(buffer.data(), buffer.size()), 0u);  // nobody typed: no block
  // What picocom does: open the slave, make it raw, type a line, read the reply.
  const int terminal = ::open(pty.slave_name().c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(terminal, 0);
  struct termios mode {};
  ASSERT_EQ(::tcgetattr(terminal, &mode), 0);
  ::cfmakeraw(&mode);
  ASSERT_EQ(::tcsetattr(terminal, TCSANOW, &mode), 0);
  ASSERT_EQ(::write(terminal, "version\r", 8), 8);
  std::size_t got = 0;
  for (int i = 0; i < 200 && got < 8; ++i) {
    got += pty.read(buffer.data() + got, buffer.size() - got);
    if (got < 8)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(got, 8u);
  EXPECT_EQ(std::memcmp(buffer.data(), "version\r", 8), 0);  // raw: CR arrives as CR
  const std::uint8_t reply[] = "ok\r\n";
  EXPECT_EQ(pty.write(reply, 4), 4u);
  char seen[4] = {};
  std::size_t read_back = 0;
  for (int i = 0; i < 200 && read_back < 4; ++i) {
    const ssize_t n = ::read(terminal, seen + read_back, 4 - read_back);
    if (n > 0)
      read_back += static_cast<std::size_t>(n);
  }
  EXPECT_EQ(std::memcmp(seen, "ok\r\n", 4), 0);
  ::close(terminal);
  // The terminal left: the stream keeps working (no hang-up).
  EXPECT_EQ(pty.read(buffer.data(), buffer.size()), 0u);
  EXPECT_EQ(pty.write(reply, 4), 4u);
}

TEST(FdByteStream, OneTerminalDescriptorForBothDirections) {
  // odocal-linux --tty: one descriptor of a serial port, read and written. A pty stands in.
  PtyByteStream far_end;
  std::string error;
  ASSERT_TRUE(far_end.open(error)) << error;
  const int tty = ::open(far_end.slave_name().c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(tty, 0);
  {
    FdByteStream stream(tty, tty);
    std::array<std::uint8_t, 16> buffer{};
    EXPECT_EQ(stream.read(buffer.data(), buffer.size()), 0u);
    const std::uint8_t line[] = {'s', 't', 'o', 'p', '\r'};
    ASSERT_EQ(far_end.write(line, 5), 5u);
    std::size_t got = 0;
    for (int i = 0; i < 200 && got < 5; ++i) {
      got += stream.read(buffer.data() + got, buffer.size() - got);
      if (got < 5)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_EQ(got, 5u);
    EXPECT_EQ(std::memcmp(buffer.data(), line, 5), 0);
    const std::uint8_t reply[] = {'o', 'k', '\r', '\n'};
    EXPECT_EQ(stream.write(reply, 4), 4u);
    std::size_t back = 0;
    for (int i = 0; i < 200 && back < 4; ++i) {
      back += far_end.read(buffer.data() + back, buffer.size() - back);
      if (back < 4)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_EQ(back, 4u);
  }
  EXPECT_EQ(::fcntl(tty, F_GETFL) & O_NONBLOCK, 0);  // the caller's descriptor is untouched
  ::close(tty);
}

TEST(PosixClock, IsMonotonicInMicroseconds) {
  PosixClock clock;
  const std::uint32_t a = clock.now_us();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::uint32_t b = clock.now_us();
  const std::uint32_t elapsed = b - a;  // modular difference
  EXPECT_GE(elapsed, 20000u);
  EXPECT_LT(elapsed, 2000000u);
}

}  // namespace
}  // namespace odocal::posix

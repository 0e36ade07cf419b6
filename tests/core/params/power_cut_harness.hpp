#pragma once
// The workloads that hold the parameter store to its promise, on any hal::BlockStore backend
// behind a FaultyFlash (faulty_flash.hpp): after any cut, a reboot loads the set being saved or
// the one saved before it, never a mix, never a set that was never saved, and a save that said
// `ok` is what the next load returns.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "faulty_flash.hpp"
#include "odocal/hal/block_store.hpp"
#include "odocal/params/param_store.hpp"

namespace odocal::test {

/// A backend under test: the faulty flash in front of it, and a reboot that builds a new driver
/// over the same medium (what survives a power cut).
struct Backend {
  std::string name;
  FaultyFlash* flash = nullptr;
  std::function<void()> reboot;
};

/// What a workload saw.
struct Outcome {
  std::size_t saves = 0u;
  std::size_t cuts = 0u;
  std::size_t recovery_cuts = 0u;
  std::size_t weak_programs = 0u;
  std::size_t lost_bits = 0u;
  std::size_t violations = 0u;  ///< broken promises (the test asserts 0 with every guard on)
  std::string first_violation;
};

inline params::ParamSet random_change(params::ParamSet set, std::mt19937& rng, std::uint16_t runs) {
  const int changes = 1 + static_cast<int>(rng() % 3u);
  for (int c = 0; c < changes; ++c) {
    const auto id = static_cast<params::ParamId>(rng() % params::param_count);
    const params::ParamInfo& info = params::param_info(id);
    float value = std::uniform_real_distribution<float>(info.min, info.max)(rng);
    if (info.integer) {
      value = static_cast<float>(static_cast<std::uint32_t>(value));
    }
    set.set(id, value);
  }
  set.wheel.method = params::FactorMethod::umbmark;
  set.wheel.runs = runs;
  set.wheel.quality_mm = static_cast<float>(rng() % 100u) * 0.5f;
  set.lateral.quality_mm = static_cast<float>(rng() % 100u) * 0.25f;
  return set;
}

/// Counts a broken promise, keeping the first one's description.
inline void note_violation(Outcome& out, const std::string& what) {
  if (out.violations++ == 0u) {
    out.first_violation = what;
  }
}

/// Saves `set` through a fresh store over `flash` (as a robot does after each boot).
inline params::StoreResult save_set(hal::BlockStore& flash, const params::StoreGuards& guards,
                                    const params::ParamSet& set) {
  params::ParamStore store(flash);
  store.set_guards(guards);
  params::StoreInfo info;
  return store.save(set, info);
}

/// Loads through a fresh store over `flash` (what a reboot finds).
inline params::StoreResult load_set(hal::BlockStore& flash, const params::StoreGuards& guards,
                                    params::ParamSet& set) {
  params::ParamStore store(flash);
  store.set_guards(guards);
  params::StoreInfo info;
  return store.load(set, info);
}

/// The operations of one uninterrupted save of `new_set` from `start`, as their sizes in bits;
/// empty (and a violation noted) when that save fails.
inline std::vector<std::size_t> save_operation_bits(Backend& b,
                                                    const std::vector<std::uint8_t>& start,
                                                    const params::ParamSet& new_set,
                                                    const params::StoreGuards& guards,
                                                    Outcome& out) {
  std::vector<std::size_t> op_bits;
  b.flash->restore(start);
  const std::size_t before = b.flash->operations();
  if (save_set(*b.flash, guards, new_set) != params::StoreResult::ok) {
    note_violation(out, b.name + ": uninterrupted save failed");
    return op_bits;
  }
  const std::size_t ops = b.flash->operations() - before;
  // An erase (a sector) comes first when the save wraps; the program is one record.
  for (std::size_t k = 0; k < ops; ++k) {
    const bool erase = ops == 2u && k == 0u;
    op_bits.push_back(8u * (erase ? b.flash->sector_size() : params::record_slot_size));
  }
  return op_bits;
}

/// After a reboot, a load must return `a` or `c` (either may be null: not a candidate); with no
/// `a`, nothing saved before, a blank or torn store is fine too. False (a violation noted) else.
inline bool load_is_one_of(Backend& b, const params::StoreGuards& guards, const params::ParamSet* a,
                           const params::ParamSet* c, const std::string& where, Outcome& out) {
  params::ParamSet loaded;
  const params::StoreResult r = load_set(*b.flash, guards, loaded);
  if (r != params::StoreResult::ok) {
    if (a == nullptr && (r == params::StoreResult::empty || r == params::StoreResult::corrupt)) {
      return true;  // nothing was saved before: blank, or a torn first record
    }
    note_violation(out, where + ": load answered " + params::to_string(r));
    return false;
  }
  if (!((a != nullptr && params::same(loaded, *a)) || (c != nullptr && params::same(loaded, *c)))) {
    note_violation(out, where + ": loaded a set that was neither being saved nor saved before");
    return false;
  }
  return true;
}

/// Recovery: the first save after a reboot from `after_cut`, cut at every byte (or every
/// `stride_bits`) of its operations; each reboot must load `found` (what the robot ran with, null
/// when none) or `recovery_set`. `last_op_bits` bounds the cut places.
inline void cut_recovery_save(Backend& b, const std::vector<std::uint8_t>& after_cut,
                              const params::ParamSet* found, const params::ParamSet& recovery_set,
                              std::size_t last_op_bits, std::size_t stride_bits,
                              const params::StoreGuards& guards, const std::string& where,
                              Outcome& out) {
  for (std::size_t rop = 0; rop < 2u; ++rop) {
    const std::size_t rstride = stride_bits > 8u ? stride_bits : 8u;
    for (std::size_t rbit = 0; rbit <= last_op_bits + 8u; rbit += rstride) {
      b.flash->restore(after_cut);
      b.flash->arm_cut(rop, rbit, true);
      (void)save_set(*b.flash, guards, recovery_set);
      const bool cut = b.flash->cuts() > 0u && b.flash->powered_off();
      b.flash->power_on();
      if (!cut) {
        break;  // the recovery save has fewer operations
      }
      ++out.recovery_cuts;
      b.reboot();
      load_is_one_of(
          b, guards, found, &recovery_set,
          where + " / recovery op " + std::to_string(rop) + " bit " + std::to_string(rbit), out);
    }
  }
}

/// Every bit of every operation of one save, from a given image, both bit orders; and after a
/// sample of those cuts, a cut at every byte (or every `stride_bits`) of the recovery save.
/// `stride_bits` thins the record cuts (1 = every bit), `erase_places` is how many places of an
/// erase are cut, `recovery_every` picks which first cuts get recovery cuts.
inline Outcome exhaustive_cuts(Backend& b, const std::vector<std::uint8_t>& start,
                               const params::ParamSet* old_set, const params::ParamSet& new_set,
                               const params::ParamSet& recovery_set, std::size_t stride_bits,
                               std::size_t recovery_every, const params::StoreGuards& guards,
                               std::size_t erase_places = 512u) {
  Outcome out;
  const std::vector<std::size_t> op_bits = save_operation_bits(b, start, new_set, guards, out);
  if (op_bits.empty()) {
    return out;
  }
  std::size_t first_index = 0u;
  for (std::size_t op = 0; op < op_bits.size(); ++op) {
    // A record is cut at every `stride_bits`; a sector erase at `erase_places` places across it.
    const std::size_t stride =
        op_bits[op] > 8u * params::record_slot_size ? op_bits[op] / erase_places : stride_bits;
    for (std::size_t bit = 0; bit <= op_bits[op]; bit += stride) {
      for (const bool msb_first : {true, false}) {
        b.flash->restore(start);
        b.flash->arm_cut(op, bit, msb_first);
        (void)save_set(*b.flash, guards, new_set);
        ++out.cuts;
        b.flash->power_on();
        b.reboot();
        const std::string where = b.name + " op " + std::to_string(op) + " bit " +
                                  std::to_string(bit) + (msb_first ? " msb" : " lsb");
        if (!load_is_one_of(b, guards, old_set, &new_set, where, out)) {
          continue;
        }
        // What the reboot found is what the robot now runs with.
        params::ParamSet found;
        const bool have = load_set(*b.flash, guards, found) == params::StoreResult::ok;
        if (first_index++ % recovery_every != 0u) {
          continue;
        }
        cut_recovery_save(b, b.flash->snapshot(), have ? &found : nullptr, recovery_set,
                          op_bits.back(), stride_bits, guards, where, out);
      }
    }
  }
  return out;
}

/// The state of `random_workload`: one flash never wiped, the sets saved on it, and what a load
/// must return now. One save at a time (`step`), each with its fault and its checks.
class RandomWorkload {
 public:
  RandomWorkload(Backend& b, std::uint32_t seed, const params::StoreGuards& guards, double cut_rate,
                 double weak_rate, double lost_bit_rate)
      : b_(b),
        guards_(guards),
        rng_(seed),
        cut_rate_(cut_rate),
        weak_rate_(weak_rate),
        lost_bit_rate_(lost_bit_rate),
        record_bits_(8u * params::record_slot_size),
        sector_bits_(8u * b.flash->sector_size()) {}

  /// Save number `i`: a new set, maybe a fault, then the checks and maybe a lost bit.
  void step(int i) {
    current_ = random_change(current_, rng_, static_cast<std::uint16_t>(i));
    history_.push_back(current_);
    ++out_.saves;
    arm_fault();
    const params::StoreResult saved = save_set(*b_.flash, guards_, current_);
    const bool was_cut = b_.flash->powered_off();
    b_.flash->disarm();
    const std::string where = b_.name + " save " + std::to_string(i);
    if (was_cut) {
      check_after_cut(where);
      recovering_ = true;  // the next save is the recovery save, cut more often
      return;
    }
    recovering_ = false;
    check_after_save(saved, where);
    lose_a_bit(where);
  }

  [[nodiscard]] const Outcome& outcome() const { return out_; }

 private:
  /// A cut at a random bit of a random operation, or else maybe a weak cell, for this save.
  void arm_fault() {
    const bool cut = chance_(rng_) < (recovering_ ? 0.5 : cut_rate_);
    const bool weak = !cut && chance_(rng_) < weak_rate_;
    if (cut) {
      // Operation 0 is an erase when the save wraps to the other sector, else the program.
      const std::size_t op = rng_() % 2u;
      const std::size_t bits = chance_(rng_) < 0.2 ? sector_bits_ : record_bits_;
      b_.flash->arm_cut(op, rng_() % (bits + 9u), rng_() % 2u == 0u);
    } else if (weak) {
      b_.flash->arm_weak_bit(rng_() % (8u * 212u));  // a bit of the record's CRC-covered bytes
      ++out_.weak_programs;
    }
  }

  /// After a cut and a reboot: load returns the set being saved or the one in force before.
  void check_after_cut(const std::string& where) {
    (recovering_ ? out_.recovery_cuts : out_.cuts) += 1;
    b_.flash->power_on();
    b_.reboot();
    params::ParamSet loaded;
    const params::StoreResult r = load_set(*b_.flash, guards_, loaded);
    if (r == params::StoreResult::ok) {
      if (!ever_saved(loaded)) {
        note_violation(out_, where + ": after a cut, loaded a set that was never saved");
      } else if (!damaged_ && !params::same(loaded, current_) &&
                 !(have_committed_ && params::same(loaded, committed_))) {
        note_violation(out_, where + ": after a cut, loaded neither the new nor the previous set");
      }
      committed_ = loaded;
      have_committed_ = true;
    } else if (have_committed_ && !damaged_) {
      note_violation(out_, where + ": after a cut, load answered " + params::to_string(r));
    }
  }

  /// After a save that ran to its end: one that said ok is what loads; a refused one (a weak
  /// cell caught by the read-back) leaves what was there.
  void check_after_save(params::StoreResult saved, const std::string& where) {
    params::ParamSet loaded;
    const params::StoreResult r = load_set(*b_.flash, guards_, loaded);
    if (saved == params::StoreResult::ok) {
      if (r != params::StoreResult::ok || !params::same(loaded, current_)) {
        note_violation(out_, where + ": save said ok but load " +
                                 (r == params::StoreResult::ok ? "returned another set"
                                                               : params::to_string(r)));
      }
      committed_ = current_;
      have_committed_ = true;
      damaged_ = false;
    } else if (r == params::StoreResult::ok) {
      if (!ever_saved(loaded) ||
          (!damaged_ && have_committed_ && !params::same(loaded, committed_))) {
        note_violation(out_, where + ": a refused save changed what loads");
      }
    }
    if (r == params::StoreResult::ok && !ever_saved(loaded)) {
      note_violation(out_, where + ": loaded a set that was never saved");
    }
  }

  /// Ageing: maybe a programmed bit somewhere in the two sectors reads 0 from now on; a load
  /// may then fail, but never return a set that was never saved.
  void lose_a_bit(const std::string& where) {
    if (chance_(rng_) < lost_bit_rate_) {
      const std::size_t address = rng_() % (2u * b_.flash->sector_size());
      if (b_.flash->lose_bit(address, rng_() % 8u)) {
        ++out_.lost_bits;
        damaged_ = true;
        params::ParamSet after;
        if (load_set(*b_.flash, guards_, after) == params::StoreResult::ok && !ever_saved(after)) {
          note_violation(out_, where + ": after a lost bit, loaded a set that was never saved");
        }
      }
    }
  }

  [[nodiscard]] bool ever_saved(const params::ParamSet& set) const {
    for (const params::ParamSet& h : history_) {
      if (params::same(h, set)) {
        return true;
      }
    }
    return false;
  }

  Backend& b_;
  const params::StoreGuards& guards_;
  std::mt19937 rng_;
  std::uniform_real_distribution<double> chance_{0.0, 1.0};
  double cut_rate_;
  double weak_rate_;
  double lost_bit_rate_;
  std::size_t record_bits_;
  std::size_t sector_bits_;
  Outcome out_;
  std::vector<params::ParamSet> history_;  ///< every set a save was started with
  bool have_committed_ = false;
  params::ParamSet committed_ = params::default_params();  ///< what a load must return now
  bool damaged_ = false;  ///< lost bits since the last good save: only "ever saved" can be asked
  params::ParamSet current_ = params::default_params();
  bool recovering_ = false;
};

/// A long random workload on one flash that is never wiped: power cuts at random bits of random
/// operations (also in the first save after a reboot), weak cells, and lost bits, damage
/// accumulating over `saves` saves. Checks after every event:
///  - a save that said ok is what the next load returns (until lost bits touch its record);
///  - after a cut, load returns the set being saved or the one in force before;
///  - load never returns a set that was never saved.
inline Outcome random_workload(Backend& b, std::uint32_t seed, int saves,
                               const params::StoreGuards& guards, double cut_rate, double weak_rate,
                               double lost_bit_rate) {
  RandomWorkload workload(b, seed, guards, cut_rate, weak_rate, lost_bit_rate);
  for (int i = 0; i < saves; ++i) {
    workload.step(i);
  }
  return workload.outcome();
}

}  // namespace odocal::test

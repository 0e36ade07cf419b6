#pragma once
// Power-cut and flash-damage injection in front of any hal::BlockStore backend (the RAM flash,
// the file store, the STM32F4 driver on its flash model), and the workloads that hold the
// parameter store to its promise: after any cut, a reboot loads the set being saved or the one
// saved before it, never a mix, never a set that was never saved, and a save that said `ok` is
// what the next load returns.
//
// Faults, all through the backend's own erase/program (so its rules still hold):
//  - a cut during an operation after `bit` bits of it took effect, in programming order: bytes
//    ascending, within a byte MSB first or LSB first (program clears bits, erase sets them);
//    `bit` past the end is a cut after the operation completed but before it returned. The
//    operation and every later one fail until power_on();
//  - a weak cell: the next program reports ok but one of its bits stays 1;
//  - a lost bit: a programmed 1 bit of the image reads 0 later (disturb, retention), which a
//    program can do at any time.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "odocal/hal/block_store.hpp"
#include "odocal/params/param_store.hpp"

namespace odocal::test {

class FaultyFlash final : public hal::BlockStore {
 public:
  explicit FaultyFlash(hal::BlockStore* inner) : inner_(inner) {}
  /// After a reboot the backend driver is a new object over the same medium.
  void retarget(hal::BlockStore* inner) { inner_ = inner; }

  /// Cut power in the operation `after_ops` operations from now, after `bit` of its bits.
  void arm_cut(std::size_t after_ops, std::size_t bit, bool msb_first) {
    cut_armed_ = true;
    cut_after_ = after_ops;
    cut_bit_ = bit;
    msb_first_ = msb_first;
  }
  /// The next program reports ok but leaves bit `bit` (of its data, in MSB-first order) at 1.
  void arm_weak_bit(std::size_t bit) {
    weak_armed_ = true;
    weak_bit_ = bit;
  }
  void disarm() { cut_armed_ = weak_armed_ = false; }
  [[nodiscard]] bool powered_off() const { return powered_off_; }
  void power_on() {
    powered_off_ = false;
    disarm();
  }
  [[nodiscard]] std::size_t operations() const { return operations_; }
  [[nodiscard]] std::size_t cuts() const { return cuts_; }

  /// Clears bit `bit` of the byte at `address` if it is 1 (a lost bit). False if it was 0.
  bool lose_bit(std::size_t address, unsigned bit) {
    // Program the unit holding it with its own contents minus that bit (flash rules: a program
    // may only clear bits, and asks for no 0 -> 1 change).
    const std::size_t g = inner_->program_granularity();
    const std::size_t base = address - address % g;
    std::vector<std::uint8_t> unit(g);
    if (inner_->read(base, unit.data(), g) != hal::StoreStatus::ok ||
        (unit[address - base] & (1u << bit)) == 0u) {
      return false;
    }
    unit[address - base] = static_cast<std::uint8_t>(unit[address - base] & ~(1u << bit));
    return inner_->program(base, unit.data(), g) == hal::StoreStatus::ok;
  }

  /// The whole image, and putting one back (bypassing the faults).
  std::vector<std::uint8_t> snapshot() {
    std::vector<std::uint8_t> image(inner_->total_size());
    EXPECT_EQ(inner_->read(0u, image.data(), image.size()), hal::StoreStatus::ok);
    return image;
  }
  void restore(const std::vector<std::uint8_t>& image) {
    const std::size_t sector = inner_->sector_size();
    for (std::size_t s = 0; s < inner_->sector_count(); ++s) {
      ASSERT_EQ(inner_->erase(s), hal::StoreStatus::ok);
      ASSERT_EQ(inner_->program(s * sector, image.data() + s * sector, sector),
                hal::StoreStatus::ok);
    }
  }

 private:
  std::size_t do_sector_size() const override { return inner_->sector_size(); }
  std::size_t do_sector_count() const override { return inner_->sector_count(); }
  std::size_t do_program_granularity() const override { return inner_->program_granularity(); }

  // True when this operation is the one cut.
  bool take() {
    ++operations_;
    if (!cut_armed_) {
      return false;
    }
    if (cut_after_ > 0u) {
      --cut_after_;
      return false;
    }
    cut_armed_ = false;
    powered_off_ = true;
    ++cuts_;
    return true;
  }
  // Mask of the bits of byte `index` that took effect when `bits` bits of the operation had.
  std::uint8_t done_mask(std::size_t index, std::size_t bits) const {
    if (bits >= (index + 1u) * 8u) {
      return 0xFFu;
    }
    if (bits <= index * 8u) {
      return 0u;
    }
    const std::size_t n = bits - index * 8u;  // 1..7 bits of this byte
    const auto low = static_cast<std::uint8_t>((1u << n) - 1u);
    return msb_first_ ? static_cast<std::uint8_t>(low << (8u - n)) : low;
  }

  hal::StoreStatus do_erase(std::size_t index) override {
    if (powered_off_) {
      return hal::StoreStatus::device_error;
    }
    if (!take()) {
      return inner_->erase(index);
    }
    // Part of the sector is erased: erase it all, then program back the bits not yet erased.
    const std::size_t size = inner_->sector_size();
    std::vector<std::uint8_t> old(size);
    if (inner_->read(index * size, old.data(), size) != hal::StoreStatus::ok ||
        inner_->erase(index) != hal::StoreStatus::ok) {
      return hal::StoreStatus::device_error;
    }
    for (std::size_t i = 0; i < size; ++i) {
      old[i] = static_cast<std::uint8_t>(old[i] | done_mask(i, cut_bit_));
    }
    (void)inner_->program(index * size, old.data(), size);
    return hal::StoreStatus::device_error;
  }

  hal::StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                              std::size_t size) override {
    if (powered_off_) {
      return hal::StoreStatus::device_error;
    }
    std::vector<std::uint8_t> landed(data, data + size);
    if (weak_armed_) {
      weak_armed_ = false;
      ++operations_;
      const std::size_t byte = (weak_bit_ / 8u) % size;
      landed[byte] = static_cast<std::uint8_t>(landed[byte] | (0x80u >> (weak_bit_ % 8u)));
      (void)inner_->program(address, landed.data(), size);
      return hal::StoreStatus::ok;  // the cell did not take the charge; nobody noticed
    }
    if (!take()) {
      return inner_->program(address, data, size);
    }
    for (std::size_t i = 0; i < size; ++i) {
      // Bits not yet programmed are still 1.
      landed[i] = static_cast<std::uint8_t>(landed[i] | ~done_mask(i, cut_bit_));
    }
    (void)inner_->program(address, landed.data(), size);
    return hal::StoreStatus::device_error;
  }

  hal::StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) override {
    return inner_->read(address, out, size);
  }

  hal::BlockStore* inner_;
  bool cut_armed_ = false;
  std::size_t cut_after_ = 0u;
  std::size_t cut_bit_ = 0u;
  bool msb_first_ = true;
  bool weak_armed_ = false;
  std::size_t weak_bit_ = 0u;
  bool powered_off_ = false;
  std::size_t operations_ = 0u;
  std::size_t cuts_ = 0u;
};

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
  const auto fail = [&out](const std::string& what) {
    if (out.violations++ == 0u) {
      out.first_violation = what;
    }
  };
  // The operations of the uninterrupted save and their sizes in bits.
  std::vector<std::size_t> op_bits;
  {
    b.flash->restore(start);
    params::ParamStore store(*b.flash);
    store.set_guards(guards);
    params::StoreInfo info;
    const std::size_t before = b.flash->operations();
    if (store.save(new_set, info) != params::StoreResult::ok) {
      fail(b.name + ": uninterrupted save failed");
      return out;
    }
    const std::size_t ops = b.flash->operations() - before;
    // An erase (a sector) comes first when the save wraps; the program is one record.
    for (std::size_t k = 0; k < ops; ++k) {
      const bool erase = ops == 2u && k == 0u;
      op_bits.push_back(8u * (erase ? b.flash->sector_size() : params::record_slot_size));
    }
  }
  const auto check_load = [&](const params::ParamSet* a, const params::ParamSet* c,
                              const std::string& where) -> bool {
    params::ParamStore store(*b.flash);
    store.set_guards(guards);
    params::ParamSet loaded;
    params::StoreInfo info;
    const params::StoreResult r = store.load(loaded, info);
    if (r != params::StoreResult::ok) {
      if (a == nullptr && (r == params::StoreResult::empty || r == params::StoreResult::corrupt)) {
        return true;  // nothing was saved before: blank, or a torn first record
      }
      fail(where + ": load answered " + params::to_string(r));
      return false;
    }
    if (!((a != nullptr && params::same(loaded, *a)) ||
          (c != nullptr && params::same(loaded, *c)))) {
      fail(where + ": loaded a set that was neither being saved nor saved before");
      return false;
    }
    return true;
  };
  std::size_t first_index = 0u;
  for (std::size_t op = 0; op < op_bits.size(); ++op) {
    // A record is cut at every `stride_bits`; a sector erase at `erase_places` places across it.
    const std::size_t stride =
        op_bits[op] > 8u * params::record_slot_size ? op_bits[op] / erase_places : stride_bits;
    for (std::size_t bit = 0; bit <= op_bits[op]; bit += stride) {
      for (const bool msb_first : {true, false}) {
        b.flash->restore(start);
        b.flash->arm_cut(op, bit, msb_first);
        {
          params::ParamStore store(*b.flash);
          store.set_guards(guards);
          params::StoreInfo info;
          (void)store.save(new_set, info);
        }
        ++out.cuts;
        b.flash->power_on();
        b.reboot();
        const std::string where = b.name + " op " + std::to_string(op) + " bit " +
                                  std::to_string(bit) + (msb_first ? " msb" : " lsb");
        if (!check_load(old_set, &new_set, where)) {
          continue;
        }
        // What the reboot found is what the robot now runs with.
        params::ParamSet found;
        bool have = false;
        {
          params::ParamStore store(*b.flash);
          store.set_guards(guards);
          params::StoreInfo info;
          have = store.load(found, info) == params::StoreResult::ok;
        }
        if (first_index++ % recovery_every != 0u) {
          continue;
        }
        // Recovery: the first save after the reboot, cut at every byte of its operations.
        const std::vector<std::uint8_t> after_cut = b.flash->snapshot();
        for (std::size_t rop = 0; rop < 2u; ++rop) {
          const std::size_t rstride = stride_bits > 8u ? stride_bits : 8u;
          for (std::size_t rbit = 0; rbit <= op_bits.back() + 8u; rbit += rstride) {
            b.flash->restore(after_cut);
            b.flash->arm_cut(rop, rbit, true);
            {
              params::ParamStore store(*b.flash);
              store.set_guards(guards);
              params::StoreInfo info;
              (void)store.save(recovery_set, info);
            }
            const bool cut = b.flash->cuts() > 0u && b.flash->powered_off();
            b.flash->power_on();
            if (!cut) {
              break;  // the recovery save has fewer operations
            }
            ++out.recovery_cuts;
            b.reboot();
            check_load(
                have ? &found : nullptr, &recovery_set,
                where + " / recovery op " + std::to_string(rop) + " bit " + std::to_string(rbit));
          }
        }
      }
    }
  }
  return out;
}

/// A long random workload on one flash that is never wiped: power cuts at random bits of random
/// operations (also in the first save after a reboot), weak cells, and lost bits, damage
/// accumulating over `saves` saves. Checks after every event:
///  - a save that said ok is what the next load returns (until lost bits touch its record);
///  - after a cut, load returns the set being saved or the one in force before;
///  - load never returns a set that was never saved.
inline Outcome random_workload(Backend& b, std::uint32_t seed, int saves,
                               const params::StoreGuards& guards, double cut_rate, double weak_rate,
                               double lost_bit_rate) {
  Outcome out;
  const auto fail = [&out](const std::string& what) {
    if (out.violations++ == 0u) {
      out.first_violation = what;
    }
  };
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  std::vector<params::ParamSet> history;  // every set a save was started with
  const auto ever_saved = [&history](const params::ParamSet& set) {
    for (const params::ParamSet& h : history) {
      if (params::same(h, set)) {
        return true;
      }
    }
    return false;
  };
  bool have_committed = false;
  params::ParamSet committed = params::default_params();  // what a load must return now
  bool damaged = false;  // lost bits since the last good save: only "ever saved" can be asked
  params::ParamSet current = params::default_params();
  const std::size_t record_bits = 8u * params::record_slot_size;
  const std::size_t sector_bits = 8u * b.flash->sector_size();

  const auto load = [&](params::ParamSet& set) {
    params::ParamStore store(*b.flash);
    store.set_guards(guards);
    params::StoreInfo info;
    return store.load(set, info);
  };
  bool recovering = false;
  for (int i = 0; i < saves; ++i) {
    current = random_change(current, rng, static_cast<std::uint16_t>(i));
    history.push_back(current);
    ++out.saves;
    const bool cut = chance(rng) < (recovering ? 0.5 : cut_rate);
    const bool weak = !cut && chance(rng) < weak_rate;
    if (cut) {
      // Operation 0 is an erase when the save wraps to the other sector, else the program.
      const std::size_t op = rng() % 2u;
      const std::size_t bits = chance(rng) < 0.2 ? sector_bits : record_bits;
      b.flash->arm_cut(op, rng() % (bits + 9u), rng() % 2u == 0u);
    } else if (weak) {
      b.flash->arm_weak_bit(rng() % (8u * 212u));  // a bit of the record's CRC-covered bytes
      ++out.weak_programs;
    }
    params::StoreResult saved;
    {
      params::ParamStore store(*b.flash);
      store.set_guards(guards);
      params::StoreInfo info;
      saved = store.save(current, info);
    }
    const bool was_cut = b.flash->powered_off();
    b.flash->disarm();
    const std::string where = b.name + " save " + std::to_string(i);
    if (was_cut) {
      (recovering ? out.recovery_cuts : out.cuts) += 1;
      b.flash->power_on();
      b.reboot();
      params::ParamSet loaded;
      const params::StoreResult r = load(loaded);
      if (r == params::StoreResult::ok) {
        if (!ever_saved(loaded)) {
          fail(where + ": after a cut, loaded a set that was never saved");
        } else if (!damaged && !params::same(loaded, current) &&
                   !(have_committed && params::same(loaded, committed))) {
          fail(where + ": after a cut, loaded neither the new nor the previous set");
        }
        committed = loaded;
        have_committed = true;
      } else if (have_committed && !damaged) {
        fail(where + ": after a cut, load answered " + params::to_string(r));
      }
      recovering = true;  // the next save is the recovery save, cut more often
      continue;
    }
    recovering = false;
    params::ParamSet loaded;
    const params::StoreResult r = load(loaded);
    if (saved == params::StoreResult::ok) {
      if (r != params::StoreResult::ok || !params::same(loaded, current)) {
        fail(where + ": save said ok but load " +
             (r == params::StoreResult::ok ? "returned another set" : params::to_string(r)));
      }
      committed = current;
      have_committed = true;
      damaged = false;
    } else if (r == params::StoreResult::ok) {
      // A refused save (weak cell caught by the read-back) leaves what was there.
      if (!ever_saved(loaded) || (!damaged && have_committed && !params::same(loaded, committed))) {
        fail(where + ": a refused save changed what loads");
      }
    }
    if (r == params::StoreResult::ok && !ever_saved(loaded)) {
      fail(where + ": loaded a set that was never saved");
    }
    // Ageing: a programmed bit somewhere in the two sectors reads 0 from now on.
    if (chance(rng) < lost_bit_rate) {
      const std::size_t address = rng() % (2u * b.flash->sector_size());
      if (b.flash->lose_bit(address, rng() % 8u)) {
        ++out.lost_bits;
        damaged = true;
        params::ParamSet after;
        if (load(after) == params::StoreResult::ok && !ever_saved(after)) {
          fail(where + ": after a lost bit, loaded a set that was never saved");
        }
      }
    }
  }
  return out;
}

}  // namespace odocal::test

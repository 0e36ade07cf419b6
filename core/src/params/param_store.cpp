#include "odocal/params/param_store.hpp"

#include <cstddef>
#include <cstring>

#include "odocal/name_list.hpp"
#include "odocal/params/crc32.hpp"

namespace odocal::params {
namespace {

// Record layout (little-endian), see docs/parameters.md:
//   0 magic u32 | 4 version u16 | 6 length u16 (bytes covered by the CRC) | 8 sequence u32
//   12 count u16 | 14 reserved u16 | 16 payload ... | length: CRC-32 u32 | 0xFF up to 256.
// Version 2 payload: count x {id u16, reserved u16, value f32}, then wheel and lateral provenance
// {method u8, reserved u8, runs u16, date u32, quality f32}.
// Version 1 payload: 13 f32 values in the order of kVersion1Order, no provenance.
constexpr std::size_t kHeaderSize = 16u;
constexpr std::size_t kCrcSize = 4u;
constexpr std::size_t kEntrySize = 8u;
constexpr std::size_t kProvenanceSize = 12u;
constexpr std::size_t kMaxEntries =
    (record_slot_size - kHeaderSize - kCrcSize - 2u * kProvenanceSize) / kEntrySize;

constexpr std::array<ParamId, 13> kVersion1Order{{
    ParamId::c_l,
    ParamId::c_r,
    ParamId::wheelbase_mm,
    ParamId::wheel_diameter_mm,
    ParamId::f_lat,
    ParamId::f_lon,
    ParamId::counts_per_rev,
    ParamId::control_hz,
    ParamId::kp,
    ParamId::ki,
    ParamId::kff,
    ParamId::max_wheel_radps,
    ParamId::cmd_timeout_ms,
}};

static_assert(param_count <= kMaxEntries, "the current record must fit one slot");
static_assert(param_count < 32u, "decode keeps the ids it has seen in the bits of a u32");
constexpr std::uint32_t kAllSeen = (1u << param_count) - 1u;
static_assert(kVersion1Order.size() < param_count, "a version-1 record is always migrated");

std::uint16_t get16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
// Forced inline: the firmware builds with -fno-inline-small-functions, which left this a call
// where the compiler makes it one load.
[[gnu::always_inline]] inline std::uint32_t get32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
float get_float(const std::uint8_t* p) {
  const std::uint32_t bits = get32(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
void put32(std::uint8_t* p, std::uint32_t v) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  std::memcpy(p, &v, sizeof v);  // one (unaligned) store on the robot
#else
  for (int i = 0; i < 4; ++i) {
    p[i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu);
  }
#endif
}
void put_float(std::uint8_t* p, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  put32(p, bits);
}

bool all_erased(const std::uint8_t* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] != 0xFFu) {
      return false;
    }
  }
  return true;
}

bool decode_provenance(const std::uint8_t* p, Provenance& out) {
  if (p[0] > static_cast<std::uint8_t>(last_factor_method)) {
    return false;
  }
  out.method = static_cast<FactorMethod>(p[0]);
  out.runs = get16(p + 2);
  out.date_unix_s = get32(p + 4);
  out.quality_mm = get_float(p + 8);
  return out.quality_mm == out.quality_mm;  // not NaN
}

static_assert(offsetof(Provenance, method) == 0u && offsetof(Provenance, reserved) == 1u &&
                  offsetof(Provenance, runs) == 2u && offsetof(Provenance, date_unix_s) == 4u &&
                  offsetof(Provenance, quality_mm) == 8u && sizeof(Provenance) == kProvenanceSize,
              "Provenance is laid out as the record's provenance");

void encode_provenance(const Provenance& in, std::uint8_t* p) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  // A Provenance holds the record's fields in the record's order with no padding (the spare byte
  // is `reserved`, always 0), so on a little-endian target it is the record's 12 bytes.
  std::memcpy(p, &in, sizeof in);
#else
  put32(p, static_cast<std::uint32_t>(in.method) | (static_cast<std::uint32_t>(in.runs) << 16));
  put32(p + 4, in.date_unix_s);
  put_float(p + 8, in.quality_mm);
#endif
}

// True when sequence a was written after b (serial-number arithmetic, wraps at 2^32).
bool later(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::int32_t>(a - b) > 0;
}

DecodeStatus decode(const std::uint8_t* data, std::size_t size, ParamSet& out, RecordInfo& info,
                    bool check_crc) {
  if (data == nullptr || size < kHeaderSize + kCrcSize) {
    return DecodeStatus::corrupt;
  }
  if (get32(data) != record_magic) {
    return all_erased(data, size) ? DecodeStatus::blank : DecodeStatus::corrupt;
  }
  const std::uint16_t version = get16(data + 4);
  const std::size_t length = get16(data + 6);
  if (length < kHeaderSize || length > size - kCrcSize) {
    return DecodeStatus::corrupt;
  }
  if (check_crc && crc32(data, length) != get32(data + length)) {
    return DecodeStatus::corrupt;
  }
  const std::uint32_t sequence = get32(data + 8);
  const std::size_t count = get16(data + 12);
  if (version > record_format_version) {
    info.version = version;
    info.sequence = sequence;
    info.migrated = false;
    return DecodeStatus::newer_version;
  }

  // One loop for both versions: a version-1 entry is the bare value, its id given by its place
  // (kVersion1Order); a version-2 entry carries its id. Version 0 was never written.
  const bool version1 = version == 1u;
  const std::size_t entry_size = version1 ? 4u : kEntrySize;
  if (version == 0u || (version1 ? count != kVersion1Order.size() : count > kMaxEntries) ||
      length != kHeaderSize + entry_size * count + (version1 ? 0u : 2u * kProvenanceSize)) {
    return DecodeStatus::corrupt;
  }
  ParamSet set = default_params();
  std::uint32_t seen = 0u;  // bit i: parameter i was in the record
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* entry = data + kHeaderSize + entry_size * i;
    const std::size_t id = version1 ? static_cast<std::size_t>(kVersion1Order[i]) : get16(entry);
    if (id >= param_count) {
      continue;  // a parameter this firmware does not know: ignored
    }
    const std::uint32_t bit = 1u << id;
    if ((seen & bit) != 0u) {
      return DecodeStatus::corrupt;
    }
    seen |= bit;
    set.values[id] = get_float(entry + entry_size - 4u);
  }
  // A record without every parameter (version 1 always) took defaults for the others.
  const bool migrated = seen != kAllSeen;
  const std::uint8_t* provenance = data + kHeaderSize + entry_size * count;
  if (version1) {
    // Version 1 kept no provenance: say so rather than claim the factors are defaults.
    set.wheel.method = FactorMethod::migrated;
    set.lateral.method = FactorMethod::migrated;
  } else if (!decode_provenance(provenance, set.wheel) ||
             !decode_provenance(provenance + kProvenanceSize, set.lateral)) {
    return DecodeStatus::corrupt;
  }
  if (!all_in_range(set)) {
    return DecodeStatus::corrupt;
  }
  out = set;
  info.version = version;
  info.sequence = sequence;
  info.migrated = migrated;
  return DecodeStatus::ok;
}

}  // namespace

DecodeStatus decode_record(const std::uint8_t* data, std::size_t size, ParamSet& out,
                           RecordInfo& info) {
  return decode(data, size, out, info, true);
}

std::size_t encode_record(const ParamSet& set, std::uint32_t sequence, std::uint8_t* out,
                          std::size_t capacity) {
  if (out == nullptr || capacity < record_slot_size) {
    return 0u;
  }
  std::memset(out, 0xFF, record_slot_size);
  const std::size_t length = kHeaderSize + kEntrySize * param_count + 2u * kProvenanceSize;
  // Pairs of u16 fields go out as one u32 (the low half first, as little-endian demands).
  put32(out, record_magic);
  put32(out + 4, static_cast<std::uint32_t>(record_format_version | (length << 16)));
  put32(out + 8, sequence);
  put32(out + 12, static_cast<std::uint32_t>(param_count));  // count, reserved 0
  for (std::size_t i = 0; i < param_count; ++i) {
    std::uint8_t* entry = out + kHeaderSize + kEntrySize * i;
    put32(entry, static_cast<std::uint32_t>(i));  // id, reserved 0
    put_float(entry + 4, set.values[i]);
  }
  std::uint8_t* provenance = out + kHeaderSize + kEntrySize * param_count;
  encode_provenance(set.wheel, provenance);
  encode_provenance(set.lateral, provenance + kProvenanceSize);
  put32(out + length, crc32(out, length));
  return length + kCrcSize;
}

const char* to_string(StoreResult result) {
  // In StoreResult's order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char messages[] =
      "ok\0no saved parameters\0record newer than this firmware\0block store failed\0"
      "store needs 2 sectors\0every stored record is damaged";
  static_assert(nul_count(messages) == static_cast<std::size_t>(StoreResult::corrupt) + 1u,
                "one message per StoreResult, in its order");
  const auto n = static_cast<unsigned>(result);
  return n <= static_cast<unsigned>(StoreResult::corrupt) ? name_at(messages, n) : "unknown";
}

ParamStore::ParamStore(hal::BlockStore& device, std::size_t first_sector)
    : device_(device), first_sector_(first_sector) {
  const std::size_t granularity = device_.program_granularity();
  const std::size_t sector = device_.sector_size();
  const std::size_t count = device_.sector_count();
  // (A granularity above the slot size leaves a remainder: no separate bound needed.)
  if (granularity != 0u && record_slot_size % granularity == 0u && sector >= record_slot_size &&
      first_sector < count && count - first_sector >= 2u) {
    slots_per_sector_ = sector / record_slot_size;
  }
}

std::size_t ParamStore::address(std::size_t sector, std::size_t slot) const {
  return sector * device_.sector_size() + slot * record_slot_size;
}

StoreResult ParamStore::read_slot(std::size_t sector, std::size_t slot, SlotBuffer& buffer) {
  return device_.read(address(sector, slot), buffer.data(), buffer.size()) == hal::StoreStatus::ok
             ? StoreResult::ok
             : StoreResult::device_error;
}

StoreResult ParamStore::scan(Scan& found, ParamSet* newest_set, SlotBuffer& buffer) {
  if (slots_per_sector_ == 0u) {
    return StoreResult::bad_geometry;
  }
  found.next_blank = slots_per_sector_;
  found.newest.sector = first_sector_;  // where save goes when there is no record
  for (std::size_t sector = first_sector_; sector < first_sector_ + 2u; ++sector) {
    for (std::size_t slot = 0; slot < slots_per_sector_; ++slot) {
      if (read_slot(sector, slot, buffer) != StoreResult::ok) {
        return StoreResult::device_error;
      }
      RecordInfo info;
      const DecodeStatus status = decode(buffer.data(), buffer.size(), scratch_, info, guards_.crc);
      if (status == DecodeStatus::blank) {
        // The slots are scanned in order, so every slot of the newest record's sector seen after
        // it is after it: the first blank one is where save goes (no second pass over the flash).
        if (sector == found.newest.sector && slot < found.next_blank) {
          found.next_blank = slot;
        }
        continue;
      }
      if (status == DecodeStatus::corrupt) {
        ++found.newest.damaged;
        continue;
      }
      if (!found.found_any || !guards_.sequence ||
          later(info.sequence, found.newest.record.sequence)) {
        found.found_any = true;
        found.newest.record = info;
        found.newest.sector = sector;
        found.newest.slot = slot;
        found.next_blank = slots_per_sector_;
        found.newest_is_newer_version = status == DecodeStatus::newer_version;
        if (status == DecodeStatus::ok && newest_set != nullptr) {
          *newest_set = scratch_;
        }
      }
    }
  }
  return StoreResult::ok;
}

StoreResult ParamStore::load(ParamSet& out, StoreInfo& info) {
  Scan found;
  ParamSet newest;
  SlotBuffer buffer;
  const StoreResult result = scan(found, &newest, buffer);
  if (result != StoreResult::ok) {
    return result;
  }
  if (!found.found_any) {
    info.damaged = found.newest.damaged;
    return found.newest.damaged > 0u ? StoreResult::corrupt : StoreResult::empty;
  }
  info = found.newest;
  if (found.newest_is_newer_version) {
    return StoreResult::newer_version;
  }
  out = newest;
  return StoreResult::ok;
}

StoreResult ParamStore::save(const ParamSet& set, StoreInfo& info) {
  Scan found;
  SlotBuffer buffer;
  const StoreResult result = scan(found, nullptr, buffer);
  if (result != StoreResult::ok) {
    return result;
  }
  // Refused after the scan (which only reads) but before anything is erased or programmed.
  if (!all_in_range(set)) {
    return StoreResult::device_error;
  }
  // With nothing found, the newest "record" is sequence 0 in the first sector.
  const std::uint32_t sequence = found.newest.record.sequence + 1u;

  // The first blank slot after the newest record, in the newest record's sector (found by scan).
  std::size_t sector = found.newest.sector;
  std::size_t slot = found.next_blank;
  if (slot == slots_per_sector_) {
    // Full: erase the other sector. It holds only older records, so the newest survives a cut.
    if (found.found_any) {
      sector = 2u * first_sector_ + 1u - sector;  // the other one of the two
    }
    slot = 0u;
    if (device_.erase(sector) != hal::StoreStatus::ok) {
      return StoreResult::device_error;
    }
  }

  const std::size_t length = encode_record(set, sequence, buffer.data(), buffer.size());
  const std::size_t granularity = device_.program_granularity();
  const std::size_t programmed = (length + granularity - 1u) / granularity * granularity;
  if (device_.program(address(sector, slot), buffer.data(), programmed) != hal::StoreStatus::ok) {
    return StoreResult::device_error;
  }
  // Read back: a record that does not decode to itself is a failed save.
  RecordInfo written;
  written.version = record_format_version;
  written.sequence = sequence;
  if (guards_.read_back) {
    if (read_slot(sector, slot, buffer) != StoreResult::ok) {
      return StoreResult::device_error;
    }
    if (decode(buffer.data(), buffer.size(), scratch_, written, guards_.crc) != DecodeStatus::ok ||
        written.sequence != sequence || !same(scratch_, set)) {
      return StoreResult::device_error;
    }
  }
  info.record = written;
  info.sector = sector;
  info.slot = slot;
  return StoreResult::ok;
}

}  // namespace odocal::params

#pragma once
/// @file
/// Power-loss-safe parameter store on a hal::BlockStore.
///
/// Two sectors (A and B) hold fixed 256-byte slots. Every `save` appends one record (header with a
/// sequence number, the values, the provenance, CRC-32) to the first blank slot after the newest
/// record; when that sector is full, the *other* sector (which holds only older records) is erased
/// and the record goes to its first slot. `load` takes the valid record with the highest sequence
/// number. A power cut at any instant therefore leaves the newest complete record untouched: a
/// half-programmed slot fails its CRC and a half-erased sector never holds the newest record.
/// docs/parameters.md describes the byte layout and the wear it causes.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/hal/block_store.hpp"
#include "odocal/params/param_table.hpp"

namespace odocal::params {

/// Bytes of one record slot on the flash (every version).
inline constexpr std::size_t record_slot_size = 256u;
/// Record format this firmware writes. Version 1 (the 13 DESIGN parameters, no provenance) is
/// migrated on load; a newer version is refused.
inline constexpr std::uint16_t record_format_version = 2u;
/// First four bytes of every record: "ODCL".
inline constexpr std::uint32_t record_magic = 0x4C43444Fu;

/// Outcome of decoding one slot.
enum class DecodeStatus : std::uint8_t {
  ok,
  blank,          ///< the slot is erased (all 0xFF)
  corrupt,        ///< wrong magic, bad length, CRC mismatch, or a value out of range
  newer_version,  ///< a whole record (CRC fine) of a format newer than this firmware's
};

/// What a decoded record says about itself.
struct RecordInfo {
  std::uint16_t version = 0u;   ///< format version found
  std::uint32_t sequence = 0u;  ///< save counter (wraps; compared modulo 2^32)
  bool migrated = false;        ///< values were filled in from defaults (older format or ids)
};

/// Decodes a record from `data` (`size` bytes, normally one slot). On `ok`, `out` holds the
/// values; otherwise `out` is untouched. `info` is filled for `ok` and `newer_version`.
/// Pure; never reads outside [data, data + size).
[[nodiscard]] DecodeStatus decode_record(const std::uint8_t* data, std::size_t size, ParamSet& out,
                                         RecordInfo& info);

/// Encodes `set` as a current-format record with `sequence` into `out` (`capacity` >= 256).
/// Unused bytes up to the slot size are 0xFF. @return bytes holding the record (CRC included),
/// or 0 when `capacity` is too small.
[[nodiscard]] std::size_t encode_record(const ParamSet& set, std::uint32_t sequence,
                                        std::uint8_t* out, std::size_t capacity);

/// Outcome of a store operation.
enum class StoreResult : std::uint8_t {
  ok,
  empty,          ///< load: the two sectors are blank (nothing was ever saved)
  newer_version,  ///< load: the newest record has a newer format; nothing loaded
  device_error,   ///< the block store failed (I/O, power cut, program verify mismatch)
  bad_geometry,   ///< the block store cannot hold the two slots sectors (see constructor)
  corrupt,        ///< load: records are there but every one is damaged; nothing loaded and nothing
            ///< erased (the image stays for inspection until the next save reuses the sectors)
};

/// Short lower-case message ("no saved parameters", ...).
[[nodiscard]] const char* to_string(StoreResult result);

/// Where the newest record lives and what it is (for tests and `status`).
struct StoreInfo {
  RecordInfo record{};
  std::size_t sector = 0u;   ///< absolute sector index
  std::size_t slot = 0u;     ///< slot index inside the sector
  std::size_t damaged = 0u;  ///< load: slots holding neither a record nor erased flash
};

/// The store's defences, all on in a product. Each one exists for a failure the others miss: the
/// CRC for a record torn by a power cut or a bit lost later; the read-back for a program that
/// reported success but did not land; the sequence number for telling the newest record once the
/// sectors have wrapped. Fault-injection tests switch one off to show a workload then fails
/// (tests/core/params/power_cut_test.cpp); nothing else should.
struct StoreGuards {
  bool crc = true;        ///< decode checks the CRC-32
  bool read_back = true;  ///< save reads the slot back and compares
  bool sequence = true;   ///< load takes the highest sequence number, not the last slot scanned
};

/// The A/B record store. Main-loop only (never from the tick or an ISR): a save erases and
/// programs flash, which may take tens of milliseconds.
class ParamStore {
 public:
  /// Uses sectors `first_sector` and `first_sector + 1` of `device`. They must exist, be at least
  /// one slot long, and the program granularity must divide the slot size; otherwise every call
  /// returns `bad_geometry`.
  ParamStore(hal::BlockStore& device, std::size_t first_sector = 0u);

  /// Loads the newest valid record into `out` (untouched unless `ok`). A version-1 record is
  /// migrated (missing parameters take their defaults, provenance `migrated`). `info` describes
  /// the record found (also for `newer_version`) and counts the damaged slots. `empty` when both
  /// sectors are blank, `corrupt` when something is written but no record is whole.
  [[nodiscard]] StoreResult load(ParamSet& out, StoreInfo& info);

  /// Appends `set` as a new record (sequence = newest + 1). Refuses (device_error) a set whose
  /// values are out of range rather than store what load would reject. On `ok`, `info` says where
  /// it went. Erases at most one sector.
  [[nodiscard]] StoreResult save(const ParamSet& set, StoreInfo& info);

  /// Replaces the guards (test builds only: see StoreGuards).
  void set_guards(const StoreGuards& guards) { guards_ = guards; }

  /// Slots per sector (0 with a bad geometry).
  [[nodiscard]] std::size_t slots_per_sector() const { return slots_per_sector_; }

 private:
  struct Scan {
    bool found_any = false;  ///< a CRC-valid record of any version exists (for sequencing)
    bool newest_is_newer_version = false;
    /// Newest loadable or newer-version record, and the count of slots neither blank nor a
    /// CRC-valid record. With no record, `sector` is the first of the two (where save starts).
    StoreInfo newest{};
    /// The first blank slot after the newest record in its sector (in the first sector with no
    /// record): where save puts the next one. slots_per_sector_ when there is none.
    std::size_t next_blank = 0u;
  };

  /// One slot's bytes. On the stack of `load` and `save` (main loop, well below the console's
  /// deepest path), not a member: 256 B of static RAM that only those two calls use.
  using SlotBuffer = std::array<std::uint8_t, record_slot_size>;

  /// Reads every slot of both sectors into `scan` (and the newest loadable set into `newest_set`
  /// when not null). bad_geometry or device_error before anything is known; never writes.
  [[nodiscard]] StoreResult scan(Scan& scan, ParamSet* newest_set, SlotBuffer& buffer);
  /// `sector` is the device's (absolute) sector index here and in `address`.
  [[nodiscard]] StoreResult read_slot(std::size_t sector, std::size_t slot, SlotBuffer& buffer);
  [[nodiscard]] std::size_t address(std::size_t sector, std::size_t slot) const;

  hal::BlockStore& device_;
  std::size_t first_sector_;
  std::size_t slots_per_sector_ = 0u;
  ParamSet scratch_{};
  StoreGuards guards_{};
};

}  // namespace odocal::params

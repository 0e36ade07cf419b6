// libFuzzer target: arbitrary flash contents under the parameter store. Whatever the flash holds,
// `load` must return only a whole, in-range set (or refuse), and a `save` must then succeed and
// be what the next `load` returns. `load` never writes; it says `empty` exactly when the flash is
// blank and `corrupt` when something is written but no record is whole. Also feeds the bytes
// straight to decode_record.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "odocal/params/param_store.hpp"
#include "odocal/sim/ram_block_store.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace odocal;
  {
    params::ParamSet set = params::default_params();
    params::RecordInfo info;
    if (params::decode_record(data, size, set, info) == params::DecodeStatus::ok &&
        !params::all_in_range(set)) {
      __builtin_trap();
    }
  }
  // Two sectors of 4 slots; the input fills the image from the start, the rest stays erased.
  static sim::StaticRamBlockStore<1024, 2, 4> flash;
  std::memset(flash.memory(), 0xFF, 2048);
  std::memcpy(flash.memory(), data, size < 2048u ? size : 2048u);
  params::ParamStore store(flash);
  params::ParamSet loaded = params::default_params();
  params::StoreInfo info;
  static std::uint8_t before[2048];
  std::memcpy(before, flash.memory(), 2048);
  const params::StoreResult result = store.load(loaded, info);
  if (result == params::StoreResult::ok && !params::all_in_range(loaded))
    __builtin_trap();
  if (std::memcmp(before, flash.memory(), 2048) != 0)
    __builtin_trap();  // load never changes the flash (a damaged image stays for inspection)
  {
    // `empty` only for blank sectors; `corrupt` only when something is written.
    bool blank = true;
    for (std::size_t i = 0; i < 2048u; ++i)
      blank = blank && before[i] == 0xFFu;
    if ((result == params::StoreResult::empty) != blank)
      __builtin_trap();
    if (result == params::StoreResult::corrupt && info.damaged == 0u)
      __builtin_trap();
  }
  if (result == params::StoreResult::device_error || result == params::StoreResult::bad_geometry) {
    __builtin_trap();  // a RAM flash never fails
  }

  // Are the sequence numbers already on the flash a consistent window (as a real store's are)?
  bool consistent = true;
  std::uint32_t first = 0u;
  bool have = false;
  for (std::size_t slot = 0; slot < 8u; ++slot) {
    params::ParamSet scratch;
    params::RecordInfo record;
    const auto status = params::decode_record(flash.memory() + slot * params::record_slot_size,
                                              params::record_slot_size, scratch, record);
    if (status == params::DecodeStatus::ok || status == params::DecodeStatus::newer_version) {
      if (!have) {
        first = record.sequence;
        have = true;
      }
      const std::uint32_t gap = record.sequence - first;
      consistent = consistent && (gap < (1u << 28) || gap > 0u - (1u << 28));
    }
  }

  params::ParamSet next = params::default_params();
  next.set(params::ParamId::c_l, 0.75f);
  next.wheel.method = params::FactorMethod::manual;
  if (store.save(next, info) != params::StoreResult::ok)
    __builtin_trap();
  params::ParamSet again;
  const params::StoreResult reloaded = store.load(again, info);
  if (reloaded != params::StoreResult::ok)
    __builtin_trap();
  if (consistent && !params::same(again, next))
    __builtin_trap();
  if (!params::all_in_range(again))
    __builtin_trap();
  return 0;
}

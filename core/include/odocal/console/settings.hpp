#pragma once
/// @file
/// The parameters in force: the one owner of the parameter set the robot runs with, whether it
/// differs from what was saved, and the ways to change it (set, load, save, defaults, factors from
/// a calibration). Every change goes through the control loop's check first, so a refused change
/// leaves the set, the loop and the store as they were. Main-loop only; no heap.

#include "odocal/drive/control_loop.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/params/param_table.hpp"

namespace odocal::console {

/// One word for a store answer, as the banner and `status` print it (`store=corrupt`).
[[nodiscard]] const char* store_word(params::StoreResult result);

class Settings {
 public:
  /// @param target_defaults this robot build's own defaults (e.g. the simulator's robot file), or
  /// nullptr for the built-in ones; ignored when out of range or refused by the drive, and where
  /// the console is linked without its target options (ConsoleOptions). Must outlive the
  /// settings.
  Settings(drive::ControlLoop& loop, params::ParamStore& store,
           const params::ParamSet* target_defaults);

  /// What `start` did.
  struct Start {
    params::StoreResult store = params::StoreResult::empty;  ///< what the store said
    bool used = false;         ///< the saved set is in force (else the defaults)
    params::StoreInfo info{};  ///< where the saved set came from (when used)
  };
  /// Loads the saved set, or the defaults when there is none or the drive refuses it, and
  /// configures the loop with it. Nothing is unsaved afterwards.
  Start start();

  /// The values in force.
  [[nodiscard]] const params::ParamSet& values() const { return values_; }
  [[nodiscard]] float get(params::ParamId id) const { return values_.get(id); }
  /// True when the values differ from what was last saved or loaded.
  [[nodiscard]] bool unsaved() const { return unsaved_; }
  /// The defaults `defaults` restores: the target's own when usable, else the built-in ones.
  /// This, `default_value` and `usable_defaults` are defined with the console's target options
  /// (console/target/).
  [[nodiscard]] params::ParamSet defaults() const;
  /// One value of `defaults()` (out of line: the built-in set is built on its frame).
  [[nodiscard, gnu::noinline]] float default_value(params::ParamId id) const;

  /// Puts `candidate` in force (unsaved) when the drive accepts it.
  drive::ConfigCheck apply(const params::ParamSet& candidate);
  /// One parameter, typed by hand: a calibration factor's provenance becomes `manual`.
  /// `value` must be in range (params::in_range).
  drive::ConfigCheck set(params::ParamId id, float value);
  /// Restores `defaults()`: unsaved, except on a robot whose store has never held a set (a
  /// restart brings these very values, so there is nothing to save).
  drive::ConfigCheck restore_defaults();

  /// Saves the values in force. @return the store's answer; on `ok` nothing is unsaved.
  params::StoreResult save(params::StoreInfo& info);

  /// What `load` did: the store's answer and, when it had a set, whether the drive took it.
  struct Load {
    params::StoreResult store = params::StoreResult::empty;
    drive::ConfigCheck check{};
    params::StoreInfo info{};
  };
  /// Reloads the saved set; on success it is in force and nothing is unsaved.
  Load load();

  /// The store's last answer to start, load or save (`status` prints it as `store=`): `corrupt`
  /// stays until a save succeeds, so a robot running on defaults over a damaged store says so.
  [[nodiscard]] params::StoreResult store_state() const { return store_state_; }

 private:
  drive::ControlLoop& loop_;
  params::ParamStore& store_;
  /// `defaults` when it is usable (in range, taken by the drive), else nullptr.
  static const params::ParamSet* usable_defaults(const params::ParamSet* defaults);

  const params::ParamSet* target_defaults_;  ///< usable target defaults, or nullptr: built-in
  params::ParamSet values_;
  bool unsaved_ = false;
  params::StoreResult store_state_ = params::StoreResult::empty;
};

}  // namespace odocal::console

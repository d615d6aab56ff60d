// rengine-bench --shortcuts: what each of the engine's shortcuts buys (time per step with
// and without it) and what it costs (the error of each run against the scene's physical
// answer, or the difference between the two runs where the shortcut claims to be exact).
#pragma once

#include <string>
#include <vector>

namespace rbench {

struct ShortcutRow {
  std::string scene;     // what the scene is
  std::string shortcut;  // which RWorldSettings::RShortcuts switch (or body property) it tests
  double onMs = 0;       // median ms per step with the shortcut
  double offMs = 0;      // and without
  double errorOn = 0;    // the run's error with the shortcut, in `unit`
  double errorOff = 0;   // and without
  std::string unit;      // what the error is
  // Sleeping scenes, where Bullet was found at build time: Bullet's times and errors with
  // its deactivation on (its defaults) and off; NaN where not run.
  double bulletOnMs, bulletOffMs, bulletErrorOn, bulletErrorOff;
};

// Runs every shortcut scene; quick: fewer bodies and steps, one grid point (a smoke run).
// Timings are medians over `repeats` timed runs after one untimed run that measures errors.
std::vector<ShortcutRow> RunShortcuts(bool quick, int repeats);
void PrintShortcutTable(const std::vector<ShortcutRow>& rows);
// False when the file cannot be written.
bool WriteShortcutCsv(const std::string& path, const std::vector<ShortcutRow>& rows);

}  // namespace rbench

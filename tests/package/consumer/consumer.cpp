// Uses the installed gearmc package: the gear model (gears/) and the build's version (core).
// Prints the version line and the base diameter d_b = m z cos(alpha) (ISO 21771) of a gear with
// m 4 mm, z 24, alpha 20 deg: 96 cos(20 deg) = 90.21 mm; tests/package checks both.
#include <cstdio>

#include "core/version.h"
#include "gears/involute_gear.h"

int main() {
  gearmc::GearParameters p;
  p.module_mm = 4.0;
  p.teeth = 24;
  p.pressure_angle_deg = 20.0;
  p.face_width_mm = 40.0;
  const gearmc::InvoluteGear gear(p);
  std::printf("%s\nbase diameter %.2f mm\n", gearmc::gearmc_version_line().c_str(),
              gear.base_diameter_mm());
  return 0;
}

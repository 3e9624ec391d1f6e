// The probing plan as a DMIS program (see dmis_plan.h).
#include "engine/plan/dmis_plan.h"

#include <cstdio>
#include <sstream>

namespace gearmc {
namespace {

// `v` with `decimals` decimals, never "-0.000…" (a value that rounds to zero is written 0).
std::string fixed_number(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string text = buffer;
  if (text[0] == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

// "x,y,z,i,j,k": point with 6 decimals (1 nm), unit vector with 9.
std::string point_and_vector(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  std::string out;
  for (int a = 0; a < 3; ++a) out += (a ? "," : "") + fixed_number(p[a], 6);
  for (int a = 0; a < 3; ++a) out += "," + fixed_number(n[a], 9);
  return out;
}

// DMIS text strings are in single quotes; a quote inside is left out.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c != '\'' && c != '\n' && c != '\r') out += c;
  }
  return out + "'";
}

}  // namespace

std::string dmis_point_label(int tooth, FlankSide side, int i, int j) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "T%03d%c_I%02d_J%02d", tooth,
                side == FlankSide::kRight ? 'R' : 'L', i, j);
  return buffer;
}

std::string dmis_program(const std::vector<PlannedPoint>& sequence, const std::string& title,
                         double approach_mm, const std::vector<std::string>& comments) {
  std::ostringstream out;
  out << "DMISMN/" << quoted(title) << ",05.3\n";
  for (const std::string& c : comments) out << "$$ " << c << "\n";
  out << "$$ " << sequence.size()
      << " points; FEAT/POINT = nominal point and outward normal, PTMEAS vector = approach "
         "vector (the probe travels along its negative)\n";
  out << "UNITS/MM,ANGDEC\n";
  char approach[64];
  std::snprintf(approach, sizeof approach, "%.3f", approach_mm);
  out << "SNSET/APPRCH," << approach << "\n";
  for (const PlannedPoint& q : sequence) {
    const std::string label = dmis_point_label(q.tooth, q.side, q.i, q.j);
    const std::string pv = point_and_vector(q.point, q.normal);
    out << "F(" << label << ")=FEAT/POINT,CART," << pv << "\n";
    out << "MEAS/POINT,F(" << label << "),1\n";
    out << "PTMEAS/CART," << pv << "\n";
    out << "ENDMES\n";
  }
  out << "ENDFIL\n";
  return out.str();
}

}  // namespace gearmc

// Tests of the readings CSV (engine/readings): exact round trip of every field, the measured
// deviation formula of docs/formats.md, and one clear message with the CSV line for each kind of
// bad input.
#include <gtest/gtest.h>

#include <string>

#include "core/input_error.h"
#include "engine/readings/readings_csv.h"

namespace gearmc {
namespace {

Readings sample(bool with_ref) {
  Readings r;
  r.stylus_radius_mm = 0.5;
  r.has_ref_dev = with_ref;
  for (int k = 0; k < 3; ++k) {
    ReadingRow row;
    row.gear = 2;
    row.tooth = 5 + k;
    row.side = k % 2 ? FlankSide::kRight : FlankSide::kLeft;
    row.i = k;
    row.j = 4 - k;
    row.order = k;
    row.p = {61.123456789012345 + k, -3.0 / 7.0, 39.445};
    row.n = Eigen::Vector3d(0.3, -0.9, 0.1 * k).normalized();
    row.c = row.p + (0.5 + 1e-3 * (0.1 + k)) * row.n;
    if (with_ref) row.ref_dev_um = 0.25 * k;
    r.rows.push_back(row);
  }
  return r;
}

TEST(ReadingsCsv, RoundTripIsExact) {
  for (bool with_ref : {false, true}) {
    const Readings a = sample(with_ref);
    const Readings b = parse_readings(format_readings(a), "r.csv");
    EXPECT_EQ(b.stylus_radius_mm, a.stylus_radius_mm);
    EXPECT_EQ(b.has_ref_dev, with_ref);
    ASSERT_EQ(b.rows.size(), a.rows.size());
    for (std::size_t k = 0; k < a.rows.size(); ++k) {
      EXPECT_EQ(b.rows[k].gear, a.rows[k].gear);
      EXPECT_EQ(b.rows[k].tooth, a.rows[k].tooth);
      EXPECT_EQ(b.rows[k].side, a.rows[k].side);
      EXPECT_EQ(b.rows[k].i, a.rows[k].i);
      EXPECT_EQ(b.rows[k].j, a.rows[k].j);
      EXPECT_EQ(b.rows[k].order, a.rows[k].order);
      EXPECT_EQ(b.rows[k].p, a.rows[k].p);  // shortest round-trip decimals: bit-exact
      EXPECT_EQ(b.rows[k].n, a.rows[k].n);
      EXPECT_EQ(b.rows[k].c, a.rows[k].c);
      EXPECT_EQ(b.rows[k].ref_dev_um, a.rows[k].ref_dev_um);
    }
  }
}

TEST(ReadingsCsv, MeasuredDeviationIsCentreOffsetAlongNormalLessRadius) {
  // docs/formats.md: e = ((c − p)·n − R)·1000 µm; the sample puts c at (R + (0.1 + k) µm) along n,
  // and ref_dev_um (0.25 k) is subtracted when present.
  const Readings r = sample(true);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(measured_deviation_um(r.rows[k], 0.5), 0.1 + k - 0.25 * k, 1e-9);
  }
}

void expect_error(const std::string& text, const std::string& message) {
  try {
    parse_readings(text, "r.csv");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

const std::string kHead =
    "# gearmc readings v1\n# stylus_radius_mm=0.5\n"
    "gear,tooth,flank,i,j,order,px,py,pz,nx,ny,nz,cx,cy,cz\n";

TEST(ReadingsCsv, BadInputGivesOneMessageWithTheLine) {
  expect_error("gear,tooth\n",
               "r.csv:1:1: header: got 'gear,tooth', expected the first line "
               "'# gearmc readings v1'");
  expect_error("# gearmc readings v1\n# stylus_radius_in=0.02\ngear\n",
               "r.csv:2:1: stylus_radius_in: got 'stylus_radius_in=0.02', expected the stylus "
               "radius in millimetres: '# stylus_radius_mm=R'");
  expect_error(
      "# gearmc readings v1\n# stylus_radius_mm=0.5\ngear,tooth,flank,i,j,order,px,py,"
      "pz,nx,ny,nz,cx,cy\n",
      "r.csv:3:51: column 15: expected 'cz' (columns: gear,tooth,flank,i,j,order,"
      "px,py,pz,nx,ny,nz,cx,cy,cz[,ref_dev_um])");
  expect_error(kHead + "0,1,L,0,0,0,60,0,10,abc,0,0,60.5,0,10\n",
               "r.csv:4:21: nx: got 'abc', expected a finite number");
  expect_error(kHead + "0,1,L,0,0,0,60,0,10,nan,0,0,60.5,0,10\n",
               "r.csv:4:21: nx: got 'nan', expected a finite number");
  expect_error(kHead + "0,1,X,0,0,0,60,0,10,1,0,0,60.5,0,10\n",
               "r.csv:4:5: flank: got 'X', expected L or R");
  expect_error(kHead + "0,1,L,0,0,0,60,0,10,1,0\n",
               "r.csv:4:24: row has 11 fields, expected 15 (as the column line)");
  expect_error(kHead + "0,1,L,0,0,0,60,0,10,2,0,0,60.5,0,10\n",
               "r.csv:4:21: nx,ny,nz: got '2,0,0', expected a unit normal (|n| = 1 within 1e-6)");
  expect_error(kHead + "0,1,L,0,0,0,60,0,10,1,0,0,60.5,0,10\n0,1,L,1,0,0,61,0,10,1,0,0,61.5,0,10\n",
               "r.csv:5:11: order: got '0', expected an order not used by an earlier row");
  expect_error(kHead, "r.csv:4:1: the readings file has no rows after its column line (line 3)");
}

}  // namespace
}  // namespace gearmc

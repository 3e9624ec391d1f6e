// Numbers as text in every output and message: the shortest decimal text that reads back as the
// same double (std::to_chars without a precision, C++17 [charconv.to.chars]), so a CSV or JSON
// number written by gearmc and read again is bit-identical, and a message echoes a value without
// invented digits ("0.1", not "0.10000000000000001").
#pragma once

#include <string>

namespace gearmc {

// Shortest round-trip text of `value` ("inf", "-inf", "nan" for the non-finite values).
std::string shortest_text(double value);

// A derived number in a message, to `digits` significant digits ("0.1235").
std::string short_text(double value, int digits = 4);

}  // namespace gearmc

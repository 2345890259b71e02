// A number as the analyses' messages write it: an integer without a decimal point, anything else
// as JSON writes a double (the shortest text that reads back the same).
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace ctb {

inline std::string NumberText(double v) {
  if (std::fabs(v - std::round(v)) < 1e-9) return std::to_string(std::llround(v));
  return nlohmann::json(v).dump();
}

}  // namespace ctb

// A number as the messages and help texts write it: 6 significant digits, printf's %.6g
// ("0.4", "1e-05", "1e+06", "nan").
#pragma once

#include <string>

namespace compaction::text {

std::string num(double v);

}  // namespace compaction::text

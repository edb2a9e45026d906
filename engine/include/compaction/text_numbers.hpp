// Strict reading of numbers from command-line text: the whole string must be the number, with
// no leading or trailing characters, and reals must be finite. Shared by compaction-run,
// compaction-server and compaction-worker, so a flag means the same thing everywhere.
#pragma once

#include <string_view>

namespace compaction {

bool parse_finite_real(std::string_view text, double& out);
bool parse_int(std::string_view text, long long& out);
bool parse_int(std::string_view text, int& out);  // false beyond the range of int

}  // namespace compaction

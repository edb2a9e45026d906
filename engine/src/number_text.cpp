#include "compaction/number_text.hpp"

#include <sstream>

namespace compaction::text {

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace compaction::text

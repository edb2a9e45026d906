// Engine version and source revision, fixed at build time (see cmake/SourceRevision.cmake).
#include "compaction/result.hpp"

namespace compaction {

const char* engine_version() { return COMPACTION_ENGINE_VERSION; }
const char* source_revision() { return COMPACTION_SOURCE_REVISION; }

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::ok: return "ok";
    case RunStatus::unstable: return "unstable";
    case RunStatus::cancelled: return "cancelled";
  }
  return "unknown";
}

bool parse(const std::string& s, RunStatus& out) {
  if (s == "ok") return out = RunStatus::ok, true;
  if (s == "unstable") return out = RunStatus::unstable, true;
  if (s == "cancelled") return out = RunStatus::cancelled, true;
  return false;
}

}  // namespace compaction

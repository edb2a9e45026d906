// One artifact of a result: a file of a run's bundle with its bytes, as a worker's upload or an
// import brings it. The queue stores it with its result (queue_store.hpp); the artifact files
// write its bytes (artifact_files.hpp).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace compaction::server {

// What a worker's upload becomes (checked by result_intake before it gets here).
struct Artifact {
  std::string name;
  std::string content_type;
  std::string data;
  // Set when the bytes were written to the artifact's file and released from `data` (an
  // import writes each run's files as it reads them): the file's size.
  std::optional<std::size_t> file_size;
};

}  // namespace compaction::server

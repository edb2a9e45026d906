// Checks a worker's upload of a finished run (summary.json and the bundle's files) against the
// job it leased, and turns it into the ResultRecord the store writes. Throws ApiError (422)
// naming the field: "summary.status", "summary.params", "files[spacetime.npy]", ...
#pragma once

#include <string>
#include <vector>

#include "compaction/bundle.hpp"
#include "store/queue_store.hpp"

namespace compaction::server {

struct UploadedFile {
  std::string name;  // the file name in the bundle
  std::string data;
};

// A bundle's files (compaction/bundle.hpp): the scene's validation caps the snapshots so that
// every valid scene's result fits.
constexpr std::size_t max_artifacts = compaction::kMaxBundleFiles;

// job_scene: the job's canonical scene; the summary's "params" must describe the same scene
// (threads may differ: it does not change the result).
// job_engine_version: the run must come from the engine version the job was queued for.
ResultRecord intake_result(const std::string& summary_text, const std::string& job_scene,
                           const std::string& job_engine_version, std::vector<UploadedFile> files);

// Content type served for an artifact name, by extension.
std::string artifact_content_type(const std::string& name);
bool valid_artifact_name(const std::string& name);

}  // namespace compaction::server

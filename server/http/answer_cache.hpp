// The answers of the reading endpoints that clients poll (the phase map, the sweeps and jobs
// lists), tagged with the version of the database they were read at: the number of write
// transactions committed since the server started (sqlite::Database::commits), beside a tag of
// this start, so that no tag of an earlier run ever matches.
//  - A request whose If-None-Match holds the current tag of its URL is answered 304, without a
//    read of the database.
//  - Otherwise the answer of the URL at the current version is built once and given to every
//    request for it until the next commit; requests that come while it is being built wait for
//    it instead of building it again. Only answers of the current version are kept, of at most
//    max_entries URLs (the most recently asked).
// A tag is read before the answer's read transaction starts, so an answer holds at least every
// commit its tag counts: a tag never names an answer older than the database.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include <httplib.h>

namespace compaction::server {

class AnswerCache {
 public:
  AnswerCache() : AnswerCache(64) {}
  explicit AnswerCache(std::size_t max_entries);

  // Answers req with the JSON text build() returns (status 200) or 304, with its ETag; version
  // is the database's (the writer's commits()), read by the caller before build reads anything.
  void serve(const httplib::Request& req, httplib::Response& res, std::uint64_t version,
             const std::function<std::string()>& build);

  // The tag of a URL (path and query) at a version: "<start>-<version>-<hash of the URL>".
  std::string tag(const std::string& url, std::uint64_t version) const;

 private:
  struct Entry {
    std::uint64_t version = 0;
    std::shared_future<std::shared_ptr<const std::string>> body;
    std::uint64_t last_used = 0;
  };

  const std::size_t max_entries_;
  const std::string start_;  // this run of the server, in hex
  std::mutex mutex_;
  std::unordered_map<std::string, Entry> entries_;
  std::uint64_t uses_ = 0;
};

// Whether an If-None-Match header (a list of tags, weak or strong, or "*") names tag.
bool if_none_match_names(const std::string& header, const std::string& tag);

}  // namespace compaction::server

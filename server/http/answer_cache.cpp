#include "http/answer_cache.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

namespace compaction::server {

namespace {

// The URL as a key: the path and the query's parameters in the order cpp-httplib keeps them
// (sorted by name), so "?a=1&b=2" and "?b=2&a=1" share an answer.
std::string url_of(const httplib::Request& req) {
  std::string url = req.path;
  char sep = '?';
  for (const auto& [k, v] : req.params) {
    url += sep + k + "=" + v;
    sep = '&';
  }
  return url;
}

std::string start_tag() {
  std::random_device rd;
  const auto now = std::chrono::system_clock::now().time_since_epoch().count();
  char buf[40];
  std::snprintf(buf, sizeof buf, "%llx%04x", static_cast<unsigned long long>(now),
                static_cast<unsigned>(rd() & 0xffffu));
  return buf;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

}  // namespace

bool if_none_match_names(const std::string& header, const std::string& tag) {
  std::size_t from = 0;
  while (from <= header.size()) {
    const std::size_t comma = header.find(',', from);
    std::string t = trim(header.substr(from, comma == std::string::npos ? std::string::npos
                                                                        : comma - from));
    if (t == "*") return true;
    if (t.rfind("W/", 0) == 0) t = t.substr(2);  // weak comparison: the tag's text alone
    if (t == tag) return true;
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return false;
}

AnswerCache::AnswerCache(std::size_t max_entries)
    : max_entries_(std::max<std::size_t>(1, max_entries)), start_(start_tag()) {}

std::string AnswerCache::tag(const std::string& url, std::uint64_t version) const {
  char buf[96];
  std::snprintf(buf, sizeof buf, "\"%s-%llx-%zx\"", start_.c_str(),
                static_cast<unsigned long long>(version), std::hash<std::string>{}(url));
  return buf;
}

void AnswerCache::serve(const httplib::Request& req, httplib::Response& res,
                        std::uint64_t version, const std::function<std::string()>& build) {
  const std::string url = url_of(req);
  const std::string etag = tag(url, version);
  res.set_header("ETag", etag);
  // Clients may keep the answer but must ask again each time (with If-None-Match).
  res.set_header("Cache-Control", "no-cache");
  if (req.has_header("If-None-Match") &&
      if_none_match_names(req.get_header_value("If-None-Match"), etag)) {
    res.status = 304;
    return;
  }
  std::shared_future<std::shared_ptr<const std::string>> body;
  std::promise<std::shared_ptr<const std::string>> building;
  bool builder = false;
  {
    std::lock_guard lock(mutex_);
    const auto it = entries_.find(url);
    if (it != entries_.end() && it->second.version == version) {
      it->second.last_used = ++uses_;
      body = it->second.body;
    } else if (it != entries_.end() && it->second.version > version) {
      // This request read the version just before a commit that another one has seen: its
      // answer is built for it alone and the newer one stays.
      body = building.get_future().share();
      builder = true;
    } else {
      // The version only grows: answers of older versions are never served again.
      std::erase_if(entries_, [&](const auto& e) { return e.second.version < version; });
      Entry& e = entries_[url];
      e.version = version;
      e.body = building.get_future().share();
      e.last_used = ++uses_;
      body = e.body;
      builder = true;
    }
    while (entries_.size() > max_entries_) {
      auto oldest = entries_.begin();
      for (auto it = entries_.begin(); it != entries_.end(); ++it) {
        if (it->second.last_used < oldest->second.last_used) oldest = it;
      }
      entries_.erase(oldest);
    }
  }
  if (builder) {
    try {
      building.set_value(std::make_shared<const std::string>(build()));
    } catch (...) {
      building.set_exception(std::current_exception());
      std::lock_guard lock(mutex_);
      const auto it = entries_.find(url);
      if (it != entries_.end() && it->second.version == version) entries_.erase(it);
    }
  }
  res.status = 200;
  res.set_content(*body.get(), "application/json");  // rethrows a failed build's exception
}

}  // namespace compaction::server

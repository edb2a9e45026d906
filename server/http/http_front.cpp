#include "http/http_front.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "http/http_util.hpp"

namespace compaction::server {

namespace {

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

const char* reason_phrase(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 401: return "Unauthorized";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Content Too Large";
    case 414: return "URI Too Long";
    case 415: return "Unsupported Media Type";
    case 417: return "Expectation Failed";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    default: return "Error";
  }
}

// The whole answer of a refusal: the API's JSON error, and the connection closes after it.
std::string answer_text(const ApiError& e) {
  const std::string body = json_text(e.body());
  return "HTTP/1.1 " + std::to_string(e.status) + " " + reason_phrase(e.status) +
         "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nConnection: close\r\nX-Content-Type-Options: nosniff\r\n\r\n" + body;
}

void set_nonblocking(int fd) {
  const int flags = ::fcntl(fd, F_GETFL, 0);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
}

// Replaces the first field line `name:` (lower case, with its colon) of the head in `in` by
// `line` (a whole field line with its CRLF; empty: the field is removed); returns the head's
// new end.
std::size_t replace_field_line(std::string& in, std::size_t head_end, std::string_view name,
                               std::string_view line) {
  std::size_t at = in.find("\r\n") + 2;  // past the request line
  while (at < head_end - 2) {
    const std::size_t next = in.find("\r\n", at) + 2;
    if (next - at >= name.size() && ::strncasecmp(in.data() + at, name.data(), name.size()) == 0) {
      in.replace(at, next - at, line);
      return head_end - (next - at) + line.size();
    }
    at = next;
  }
  return head_end;
}

// Whether an Accept-Encoding value (RFC 9110 12.5.3) takes gzip: "gzip" or "*" without q=0.
bool accepts_gzip(std::string_view value) {
  const auto trim = [](std::string_view t) {
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
    while (!t.empty() && (t.back() == ' ' || t.back() == '\t')) t.remove_suffix(1);
    return t;
  };
  while (!value.empty()) {
    const std::size_t comma = value.find(',');
    std::string_view item = value.substr(0, comma);
    value = comma == std::string_view::npos ? std::string_view() : value.substr(comma + 1);
    const std::size_t semi = item.find(';');
    const std::string_view coding = trim(item.substr(0, semi));
    const bool gzip = coding.size() == 4 && ::strncasecmp(coding.data(), "gzip", 4) == 0;
    if (!gzip && coding != "*") continue;
    if (semi == std::string_view::npos) return true;
    std::string_view q = trim(item.substr(semi + 1));
    if (q.size() < 2 || (q[0] != 'q' && q[0] != 'Q') || q[1] != '=') return true;
    q.remove_prefix(2);
    return q.find_first_not_of("0.") != std::string_view::npos;  // q=0, 0.0, 0.000: refused
  }
  return false;
}

constexpr std::size_t kReadChunk = 16 << 10;
constexpr int kReadsPerWake = 16;  // at most 256 KiB from one connection before the others
constexpr std::size_t kDrainBytes = 64u << 20;
constexpr auto kScanInterval = std::chrono::milliseconds(100);

}  // namespace

Clock::time_point paced_deadline(Clock::time_point start, std::size_t bytes,
                                 const ConnectionLimits& limits, Clock::time_point hard) {
  const double allowed = limits.body_grace_seconds +
                         static_cast<double>(bytes) / std::max(1.0, limits.min_body_rate);
  return std::min(hard, start + seconds(allowed));
}

ConnectionFront::ConnectionFront(const ConnectionLimits& limits, HeadCheck check,
                                 Dispatch dispatch, Refused refused)
    : limits_(limits),
      check_(std::move(check)),
      dispatch_(std::move(dispatch)),
      refused_(std::move(refused)) {
  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (epoll_fd_ < 0 || wake_fd_ < 0) {
    throw std::runtime_error(std::string("cannot create the connection front: ") + std::strerror(errno));
  }
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = wake_fd_;
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, wake_fd_, &ev);
}

ConnectionFront::~ConnectionFront() {
  stop();
  ::close(wake_fd_);
  ::close(epoll_fd_);
}

void ConnectionFront::start() {
  stopping_ = false;
  thread_ = std::thread([this] { run(); });
}

void ConnectionFront::stop() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof one);
  thread_.join();
  std::lock_guard lock(mutex_);
  for (int fd : adopted_) {
    ::close(fd);
    --open_;
  }
  adopted_.clear();
  for (auto& [c, after] : returned_) {
    ::close(c->fd);
    --open_;
  }
  returned_.clear();
}

void ConnectionFront::adopt(int fd) {
  if (open_.fetch_add(1) >= limits_.max_connections) {
    const std::string text = answer_text(ApiError(503, "request", "too many open connections"));
    [[maybe_unused]] const auto n = ::send(fd, text.data(), text.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    ::close(fd);
    --open_;
    return;
  }
  {
    std::lock_guard lock(mutex_);
    if (stopping_) {
      ::close(fd);
      --open_;
      return;
    }
    adopted_.push_back(fd);
  }
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof one);
}

void ConnectionFront::give_back(std::unique_ptr<Connection> c, bool drain) {
  {
    std::lock_guard lock(mutex_);
    if (!stopping_) {
      returned_.emplace_back(std::move(c), drain);
    }
  }
  if (c) {  // the front has stopped
    ::close(c->fd);
    --open_;
    return;
  }
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof one);
}

void ConnectionFront::upload_done() {
  {
    std::lock_guard lock(mutex_);
    ++uploads_done_;
  }
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto n = ::write(wake_fd_, &one, sizeof one);
}

void ConnectionFront::run() {
  std::array<epoll_event, 256> events;
  auto next_scan = Clock::now() + kScanInterval;
  while (!stopping_) {
    const int n = ::epoll_wait(epoll_fd_, events.data(), static_cast<int>(events.size()),
                               static_cast<int>(kScanInterval.count()));
    bool woken = false;
    for (int i = 0; i < n; ++i) {
      const int fd = events[i].data.fd;
      if (fd == wake_fd_) {
        woken = true;
        continue;
      }
      const auto it = held_.find(fd);
      if (it != held_.end()) on_event(*it->second, events[i].events);
    }
    // Last, so that an event of this round never meets a new connection on a reused fd.
    if (woken) take_handed_over();
    const auto now = Clock::now();
    if (now >= next_scan) {
      expire(now);
      next_scan = now + kScanInterval;
    }
  }
  for (auto& [fd, c] : held_) {
    ::close(fd);
    --open_;
  }
  held_.clear();
  upload_queue_.clear();
  buffered_ = 0;
}

void ConnectionFront::take_handed_over() {
  std::uint64_t count;
  [[maybe_unused]] const auto r = ::read(wake_fd_, &count, sizeof count);
  std::vector<int> adopted;
  std::vector<std::pair<std::unique_ptr<Connection>, bool>> returned;
  {
    std::lock_guard lock(mutex_);
    adopted.swap(adopted_);
    returned.swap(returned_);
    uploads_running_ -= uploads_done_;
    uploads_done_ = 0;
  }
  const auto now = Clock::now();
  for (int fd : adopted) {
    set_nonblocking(fd);
    int yes = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    auto c = std::make_unique<Connection>();
    c->fd = fd;
    c->phase = Connection::Phase::idle;
    c->deadline = now + seconds(limits_.header_timeout_seconds);
    Connection& ref = *c;
    held_.emplace(fd, std::move(c));
    watch(ref, EPOLLIN | EPOLLRDHUP);
  }
  for (auto& [c, drain] : returned) {
    const int fd = c->fd;
    Connection& ref = *c;
    held_.emplace(fd, std::move(c));
    ref.scanned = 0;
    ref.request_bytes = 0;
    ref.body_buffered = false;
    ref.reserved = 0;
    if (drain) {
      ref.in.clear();
      ::shutdown(fd, SHUT_WR);
      ref.phase = Connection::Phase::draining;
      ref.deadline = now + std::chrono::seconds(2);
      watch(ref, EPOLLIN | EPOLLRDHUP);
      continue;
    }
    ref.phase = Connection::Phase::idle;
    ref.deadline = now + seconds(limits_.keep_alive_seconds);
    watch(ref, EPOLLIN | EPOLLRDHUP);
    // A pipelined request already in: count its bytes and read on.
    if (!ref.in.empty()) {
      ref.reserved = ref.in.size();
      buffered_ += ref.reserved;
      read_request(ref);
    }
  }
  while (uploads_running_ < limits_.upload_slots && !upload_queue_.empty()) {
    const int fd = upload_queue_.front();
    upload_queue_.pop_front();
    const auto it = held_.find(fd);
    if (it == held_.end() || it->second->phase != Connection::Phase::upload_wait) continue;
    ++uploads_running_;
    hand_to_handler(*it->second, true);
  }
}

void ConnectionFront::watch(Connection& c, std::uint32_t events) {
  epoll_event ev{};
  ev.events = events;
  ev.data.fd = c.fd;
  if (::epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, c.fd, &ev) != 0 && errno == ENOENT) {
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, c.fd, &ev);
  }
}

void ConnectionFront::release_budget(Connection& c) {
  buffered_ -= std::min(buffered_, c.reserved);
  c.reserved = 0;
}

void ConnectionFront::close_connection(int fd) {
  const auto it = held_.find(fd);
  if (it == held_.end()) return;
  release_budget(*it->second);
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  ::close(fd);
  held_.erase(it);
  --open_;
}

void ConnectionFront::hand_to_handler(Connection& c, bool large) {
  const int fd = c.fd;
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  release_budget(c);
  c.body_buffered = !large;
  auto it = held_.find(fd);
  std::unique_ptr<Connection> owned = std::move(it->second);
  held_.erase(it);
  dispatch_(std::move(owned), large);
}

void ConnectionFront::on_event(Connection& c, std::uint32_t events) {
  using Phase = Connection::Phase;
  switch (c.phase) {
    case Phase::idle:
    case Phase::head:
    case Phase::body:
      if (events & (EPOLLIN | EPOLLHUP | EPOLLRDHUP | EPOLLERR)) read_request(c);
      return;
    case Phase::upload_wait:
      // Only a hang-up is watched: the body waits in the socket for its handler.
      if (events & (EPOLLHUP | EPOLLERR | EPOLLRDHUP)) close_connection(c.fd);
      return;
    case Phase::refusing:
      if (events & (EPOLLHUP | EPOLLERR)) {
        close_connection(c.fd);
        return;
      }
      if (events & EPOLLOUT) write_out(c);
      return;
    case Phase::draining: {
      std::array<char, kReadChunk> sink;
      for (int i = 0; i < kReadsPerWake; ++i) {
        const ssize_t n = ::recv(c.fd, sink.data(), sink.size(), 0);
        if (n > 0) {
          c.out_done += static_cast<std::size_t>(n);
          if (c.out_done > kDrainBytes) break;
          continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;
        break;  // the client closed, or an error
      }
      close_connection(c.fd);
      return;
    }
  }
}

void ConnectionFront::read_request(Connection& c) {
  using Phase = Connection::Phase;
  const int fd = c.fd;
  bool peer_closed = false;
  std::array<char, kReadChunk> buf;
  for (int i = 0; i < kReadsPerWake; ++i) {
    const ssize_t n = ::recv(fd, buf.data(), buf.size(), 0);
    if (n > 0) {
      const auto got = static_cast<std::size_t>(n);
      // The bytes held count against the budget as they arrive.
      if (buffered_ + got > limits_.buffer_budget) {
        refuse(c, ApiError(503, "request", "the server is holding too many unfinished requests"),
               "", "");
        return;
      }
      buffered_ += got;
      c.reserved += got;
      c.in.append(buf.data(), got);
      if (got < buf.size()) break;
      continue;
    }
    if (n == 0) {
      peer_closed = true;
      break;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) break;
    close_connection(fd);
    return;
  }

  const auto now = Clock::now();
  if (c.phase == Phase::idle && !c.in.empty()) {
    c.phase = Phase::head;
    c.deadline = now + seconds(limits_.header_timeout_seconds);
    c.request_deadline = now + seconds(limits_.request_timeout_seconds);
  }
  if (c.phase == Phase::head) {
    const auto end = find_head_end(c.in, c.scanned);
    if (!end || *end > limits_.max_header_bytes) {
      c.scanned = c.in.size();
      if (c.in.size() > limits_.max_header_bytes) {
        refuse(c, ApiError(431, "request", "the request's head is larger than " +
                                               std::to_string(limits_.max_header_bytes) + " bytes"),
               "", "");
        return;
      }
    } else {
      c.request_bytes = *end;  // the head; head_complete adds the body
      head_complete(c);
      if (held_.find(fd) == held_.end() || c.phase != Phase::body) return;
    }
  }
  if (c.phase == Phase::body && c.in.size() >= c.request_bytes) {
    hand_to_handler(c, false);
    return;
  }
  if (peer_closed) close_connection(fd);
}

void ConnectionFront::head_complete(Connection& c) {
  std::size_t head_end = c.request_bytes;
  const auto parsed = parse_request_head(std::string_view(c.in).substr(0, head_end - 2));
  if (const auto* e = std::get_if<HeadError>(&parsed)) {
    refuse(c, ApiError(e->status, e->field, e->message), "", "");
    return;
  }
  const RequestHead& head = std::get<RequestHead>(parsed);
  if (auto refusal = check_(head)) {
    refuse(c, *refusal, head.method, head.path);
    return;
  }
  const std::size_t length = head.content_length.value_or(0);
  // Answers are compressed with gzip or not at all: cpp-httplib 0.11 compresses brotli at its
  // quality 11, about 1 MB/s, so a run table's 12.7 MB CSV took 15 s to a browser and its
  // request was cut (bench/results/feature_plot.md); gzip does it at tens of MB/s.
  if (const std::string* encodings = head.find("Accept-Encoding")) {
    head_end = replace_field_line(c.in, head_end, "accept-encoding:",
                                  accepts_gzip(*encodings) ? "Accept-Encoding: gzip\r\n" : "");
  }
  if (head.expect_continue) {
    head_end = replace_field_line(c.in, head_end, "expect:", "");
    if (c.in.size() < head_end + length) {
      static constexpr std::string_view go = "HTTP/1.1 100 Continue\r\n\r\n";
      if (::send(c.fd, go.data(), go.size(), MSG_DONTWAIT | MSG_NOSIGNAL) !=
          static_cast<ssize_t>(go.size())) {
        close_connection(c.fd);
        return;
      }
    }
  }
  c.request_bytes = head_end + length;
  if (length > limits_.front_body_bytes) {
    start_upload(c);
    return;
  }
  c.phase = Connection::Phase::body;
  c.body_started = Clock::now();
  c.scanned = head_end;  // where the body starts
  c.deadline = paced_deadline(c.body_started, 0, limits_, c.request_deadline);
}

void ConnectionFront::start_upload(Connection& c) {
  c.phase = Connection::Phase::upload_wait;
  c.deadline = c.request_deadline;
  if (uploads_running_ < limits_.upload_slots && upload_queue_.empty()) {
    ++uploads_running_;
    hand_to_handler(c, true);
    return;
  }
  watch(c, EPOLLRDHUP);
  upload_queue_.push_back(c.fd);
}

void ConnectionFront::refuse(Connection& c, const ApiError& e, const std::string& method,
                             const std::string& path) {
  refused_(method, path, e);
  release_budget(c);
  c.in.clear();
  c.in.shrink_to_fit();
  c.out = answer_text(e);
  c.out_done = 0;
  c.phase = Connection::Phase::refusing;
  c.deadline = Clock::now() + seconds(limits_.idle_timeout_seconds);
  watch(c, EPOLLOUT);
  write_out(c);
}

void ConnectionFront::write_out(Connection& c) {
  while (c.out_done < c.out.size()) {
    const ssize_t n = ::send(c.fd, c.out.data() + c.out_done, c.out.size() - c.out_done,
                             MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      c.out_done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;  // EPOLLOUT resumes it
    close_connection(c.fd);
    return;
  }
  // Answered: read (and drop) what the client still sends for a short while, so that a client
  // writing its whole body before it reads sees the answer instead of a reset.
  c.out.clear();
  c.out.shrink_to_fit();
  c.out_done = 0;
  ::shutdown(c.fd, SHUT_WR);
  c.phase = Connection::Phase::draining;
  c.deadline = Clock::now() + std::chrono::seconds(2);
  watch(c, EPOLLIN | EPOLLRDHUP);
}

void ConnectionFront::expire(Clock::time_point now) {
  using Phase = Connection::Phase;
  std::vector<int> due;
  for (auto& [fd, c] : held_) {
    if (c->phase == Phase::body) {
      const std::size_t body = c->in.size() - std::min(c->in.size(), c->scanned);
      c->deadline = paced_deadline(c->body_started, body, limits_, c->request_deadline);
    }
    if (c->deadline <= now) due.push_back(fd);
  }
  for (int fd : due) {
    Connection& c = *held_.at(fd);
    switch (c.phase) {
      case Phase::head:
        refuse(c, ApiError(408, "request", "the request's head did not arrive within " +
                                               std::to_string(static_cast<int>(limits_.header_timeout_seconds)) +
                                               " s"),
               "", "");
        break;
      case Phase::body:
        refuse(c, ApiError(408, "body", "the body came slower than " +
                                            std::to_string(static_cast<int>(limits_.min_body_rate)) +
                                            " bytes/s, or did not end within the request's time"),
               "", "");
        break;
      case Phase::upload_wait:
        refuse(c, ApiError(503, "body", "every upload slot stayed busy; send the request again"), "", "");
        break;
      case Phase::idle:
      case Phase::refusing:
      case Phase::draining:
        close_connection(fd);
        break;
    }
  }
}

}  // namespace compaction::server

// The connection front of compaction-server's HTTP server: one thread that holds every client
// connection in an epoll set while it is idle or while its request arrives, so that a handler
// thread is spent only on a request that is complete (or, for a large body, that is admitted to
// one of a few upload slots). A client that sends nothing, sends its head a byte at a time or
// trickles its body costs a socket and its buffered bytes, never a thread: a thousand of each
// leave /api/v1/health answering at once (tests/e2e/server_slow_clients_test.py).
//
// The rules of a connection, in the order a request meets them:
//  - a new or kept-alive connection must start its next request within header_timeout (new)
//    or keep_alive (after an answer), else it is closed;
//  - the head must end within header_timeout of its first byte and hold at most
//    max_header_bytes; it is read strictly (http_head.hpp) and checked (the request guard:
//    token, origin, length, type) before a byte of the body is read; a refusal is answered by
//    the front and the connection closed after a bounded drain;
//  - the head's Accept-Encoding becomes "gzip" when it takes gzip and is removed otherwise:
//    answers are gzip or plain, never brotli (cpp-httplib 0.11's brotli, at quality 11, runs at
//    about 1 MB/s and cut a 12.7 MB CSV at its write deadline);
//  - a body of at most front_body_bytes is buffered here; a larger one waits for one of
//    upload_slots and is read by its handler; either way the body must keep pace: it may take
//    body_grace plus one second per min_body_rate bytes (mod_reqtimeout's MinRate rule), and
//    never more than request_timeout;
//  - the front's buffers hold at most buffer_budget bytes in all: a connection whose bytes
//    would pass it is refused (503);
//  - at most max_connections connections are open; one more is answered 503 and closed.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "http/http_head.hpp"
#include "input/api_error.hpp"

namespace compaction::server {

struct ConnectionLimits {
  double header_timeout_seconds = 10;    // a request's head complete, from its first byte
  double keep_alive_seconds = 5;         // wait for the next request on an idle connection
  double body_grace_seconds = 10;        // a body's time before its pace is counted
  double min_body_rate = 16 << 10;       // bytes per second a body must keep after its grace
  double request_timeout_seconds = 300;  // the whole exchange of one request, at most
  double idle_timeout_seconds = 10;      // longest silence while a handler reads or writes
  std::size_t max_header_bytes = 64 << 10;
  std::size_t front_body_bytes = 1 << 20;      // bodies buffered by the front, at most
  std::size_t buffer_budget = 256u << 20;      // all buffered heads and bodies together
  int upload_slots = 4;                  // larger bodies read by handlers at once
  int max_threads = 128;                 // requests handled at once
  int max_connections = 8192;            // open connections (also capped by RLIMIT_NOFILE)
  int listen_backlog = 1024;             // connections waiting to be accepted (the kernel caps
                                         // it at net.core.somaxconn)
};

using Clock = std::chrono::steady_clock;

// The most time a transfer of `bytes` so far may have taken: grace plus bytes / rate after
// `start`, and never beyond `hard` (the request's deadline).
Clock::time_point paced_deadline(Clock::time_point start, std::size_t bytes,
                                 const ConnectionLimits& limits, Clock::time_point hard);

// A client connection, held by the front or by the handler serving its request.
struct Connection {
  int fd = -1;
  std::string in;             // bytes received and not yet consumed by a request
  std::size_t request_bytes = 0;  // the current request's head and body, once the head is read
  bool body_buffered = false; // the whole current request is in `in`
  int served = 0;             // requests answered on the connection
  Clock::time_point request_deadline{};  // the current request's hard deadline

  // The front's own state.
  enum class Phase { idle, head, body, upload_wait, refusing, draining } phase = Phase::idle;
  Clock::time_point deadline{};
  Clock::time_point body_started{};
  std::size_t scanned = 0;    // where the search for the head's end resumes
  std::size_t reserved = 0;   // bytes of buffer_budget this connection's buffer holds
  std::string out;            // an answer the front writes itself
  std::size_t out_done = 0;
};

class ConnectionFront {
 public:
  // The request guard: a reason to refuse a request whose head is in, or nothing.
  using HeadCheck = std::function<std::optional<ApiError>(const RequestHead&)>;
  // Serves the connection's request on a handler thread (large: its body is not all in `in`,
  // and it holds an upload slot until upload_done()).
  using Dispatch = std::function<void(std::unique_ptr<Connection>, bool large)>;
  // A request the front answered itself (method and path empty when the head was unreadable).
  using Refused = std::function<void(const std::string& method, const std::string& path,
                                     const ApiError& error)>;

  ConnectionFront(const ConnectionLimits& limits, HeadCheck check, Dispatch dispatch,
                  Refused refused);
  ~ConnectionFront();
  ConnectionFront(const ConnectionFront&) = delete;
  ConnectionFront& operator=(const ConnectionFront&) = delete;

  void start();
  // Closes every connection the front holds; returned ones are closed from then on.
  void stop();

  // Thread-safe: a new connection from the listener.
  void adopt(int fd);
  // Thread-safe: a handler answered a request and the connection stays open (`in` holds what
  // the client sent beyond it); drain: the answer was the last, close after a bounded drain.
  void give_back(std::unique_ptr<Connection> c, bool drain);
  // Thread-safe: a large request's handler is done with its upload slot.
  void upload_done();

  int open_connections() const { return open_.load(); }

 private:
  void run();
  void take_handed_over();
  void on_event(Connection& c, std::uint32_t events);
  void read_request(Connection& c);
  void head_complete(Connection& c);
  void start_upload(Connection& c);
  void refuse(Connection& c, const ApiError& e, const std::string& method, const std::string& path);
  void write_out(Connection& c);
  void expire(Clock::time_point now);
  void watch(Connection& c, std::uint32_t events);
  void hand_to_handler(Connection& c, bool large);
  void close_connection(int fd);
  void release_budget(Connection& c);

  const ConnectionLimits limits_;
  HeadCheck check_;
  Dispatch dispatch_;
  Refused refused_;
  int epoll_fd_ = -1;
  int wake_fd_ = -1;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> open_{0};

  // Handed over by other threads.
  std::mutex mutex_;
  std::vector<int> adopted_;
  std::vector<std::pair<std::unique_ptr<Connection>, bool>> returned_;
  int uploads_done_ = 0;

  // The front thread's own.
  std::unordered_map<int, std::unique_ptr<Connection>> held_;
  std::deque<int> upload_queue_;  // fds waiting for an upload slot, in order
  int uploads_running_ = 0;
  std::size_t buffered_ = 0;      // bytes of buffer_budget held
};

}  // namespace compaction::server

// The HTTP server of compaction-server: cpp-httplib's request handling on connections it
// serves itself, so that no client can hold a handler thread for long or crowd others out.
//
//  - A request's line and headers must arrive within header_timeout and hold at most
//    max_header_bytes; the whole request (body and response included) ends by
//    request_timeout; a pause of idle_timeout on the socket ends it too (slowloris).
//  - Handler threads start on demand, up to max_threads connections served at once; an idle
//    thread beyond the first few ends after a minute.
//  - A request the guard refuses before its body (request_guard.hpp) gets its answer and the
//    connection is closed after a bounded drain of what the client still sends, so a refused
//    body is never read into memory and never parsed as the next request.
//  - TCP_NODELAY on every connection (no 40 ms stall between headers and body on keep-alive),
//    and SO_REUSEADDR without SO_REUSEPORT: a second server on a busy port fails to bind.
//  - A listen backlog of listen_backlog connections (cpp-httplib's library listens with 5: a
//    few dozen workers or readers connecting at once overflowed it, and the connections beyond
//    waited for the client's SYN retries, 1, 3, 7, 15 s, or were reset).
#pragma once

#include <cstddef>

#include <httplib.h>

namespace compaction::server {

struct ConnectionLimits {
  double header_timeout_seconds = 10;    // request line and headers complete
  double request_timeout_seconds = 300;  // the whole exchange of one request
  double idle_timeout_seconds = 10;      // longest silence while reading or writing
  double keep_alive_seconds = 5;         // wait for the next request on an idle connection
  std::size_t max_header_bytes = 64 << 10;
  int max_threads = 128;                 // connections served at once
  int listen_backlog = 1024;             // connections waiting to be accepted (the kernel caps
                                         // it at net.core.somaxconn)
};

class HttpServer : public httplib::Server {
 public:
  explicit HttpServer(ConnectionLimits limits = {});

  const ConnectionLimits& connection_limits() const { return limits_; }

  // Serves the bound socket (bind_to_port, bind_to_any_port) with the listen backlog of the
  // limits, until stop().
  bool listen_after_bind();

  // Called by the request guard on the thread handling the request: the headers are in
  // (the header deadline and byte cap no longer apply).
  static void headers_complete();
  // The answer is final and the connection closes after it (a refused body stays unread).
  static void close_after_response();

 private:
  bool process_and_close_socket(socket_t sock) override;

  ConnectionLimits limits_;
};

}  // namespace compaction::server

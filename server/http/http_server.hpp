// The HTTP server of compaction-server: cpp-httplib's request handling behind a connection
// front (http_front.hpp) that holds every connection while it is idle or while its request
// arrives, so that no client can hold a handler thread by being slow or silent.
//
//  - The listener hands each accepted socket to the front; the front reads the request's head
//    strictly (http_head.hpp), runs the head check (the request guard) and buffers the body,
//    then gives the complete request to a handler thread; a large body is read by its handler
//    in one of a few upload slots, at the front's pace rule.
//  - Handler threads start on demand, up to max_threads requests at once; an idle thread
//    beyond the first few ends after a minute. After the answer the connection goes back to
//    the front for its next request (keep-alive), with any pipelined bytes.
//  - A handler's reads and writes wait at most idle_timeout each and never past the request's
//    deadline; its writes keep the body's pace rule too (a client that does not read its
//    answer is cut).
//  - TCP_NODELAY on every connection (no 40 ms stall between headers and body on keep-alive),
//    and SO_REUSEADDR without SO_REUSEPORT: a second server on a busy port fails to bind.
//  - A listen backlog of listen_backlog connections (cpp-httplib's library listens with 5: a
//    few dozen workers or readers connecting at once overflowed it, and the connections beyond
//    waited for the client's SYN retries, 1, 3, 7, 15 s, or were reset).
#pragma once

#include <memory>

#include <httplib.h>

#include "http/http_front.hpp"

namespace compaction::server {

class HandlerPool;

class HttpServer : public httplib::Server {
 public:
  explicit HttpServer(ConnectionLimits limits = {});
  ~HttpServer() override;

  const ConnectionLimits& connection_limits() const { return limits_; }

  // The check of a request's head before its body is read (the request guard).
  void set_head_check(ConnectionFront::HeadCheck check) { head_check_ = std::move(check); }
  // Told of every request the front answered itself (a refused head, a slow client).
  void set_refusal_logger(ConnectionFront::Refused logger) { refusal_logger_ = std::move(logger); }

  // Serves the bound socket (bind_to_port, bind_to_any_port) with the listen backlog of the
  // limits, until stop().
  bool listen_after_bind();

  // Open client connections (the front's and the handlers').
  int open_connections() const { return front_ ? front_->open_connections() : 0; }

  // Called by a handler: the answer is final and the connection closes after it (what the
  // client still sends is drained for a moment, never parsed as a next request).
  static void close_after_response();

 private:
  bool process_and_close_socket(socket_t sock) override;
  void serve(std::unique_ptr<Connection> c, bool large);

  ConnectionLimits limits_;
  ConnectionFront::HeadCheck head_check_;
  ConnectionFront::Refused refusal_logger_;
  std::unique_ptr<ConnectionFront> front_;
  std::unique_ptr<HandlerPool> pool_;
};

}  // namespace compaction::server

#include "http_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>

namespace compaction::server {

namespace {

using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// Milliseconds until `until`, at most `cap`; 0 or less when it has passed.
int ms_until(Clock::time_point until, Clock::duration cap) {
  const auto left = std::min(until - Clock::now(), cap);
  return static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(left).count());
}

bool wait_for(int fd, short events, int timeout_ms) {
  if (timeout_ms <= 0) return false;
  pollfd p{fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, timeout_ms);
    if (r < 0 && errno == EINTR) continue;
    return r > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
  }
}

void address_of(int fd, bool peer, std::string& ip, int& port) {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  const int r = peer ? ::getpeername(fd, reinterpret_cast<sockaddr*>(&a), &len)
                     : ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  if (r != 0) return;
  char buf[INET6_ADDRSTRLEN] = {};
  if (a.ss_family == AF_INET) {
    const auto* in = reinterpret_cast<const sockaddr_in*>(&a);
    ::inet_ntop(AF_INET, &in->sin_addr, buf, sizeof buf);
    port = ntohs(in->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* in = reinterpret_cast<const sockaddr_in6*>(&a);
    ::inet_ntop(AF_INET6, &in->sin6_addr, buf, sizeof buf);
    port = ntohs(in->sin6_port);
  }
  ip = buf;
}

// A socket with a deadline: every read and write waits at most the idle timeout and never past
// the deadline of the request; while the headers are read, the bytes are counted and capped.
class DeadlineStream final : public httplib::Stream {
 public:
  DeadlineStream(int fd, const ConnectionLimits& limits) : fd_(fd), limits_(limits) {}

  void start_request() {
    const auto now = Clock::now();
    header_deadline_ = now + seconds(limits_.header_timeout_seconds);
    request_deadline_ = now + seconds(limits_.request_timeout_seconds);
    in_headers_ = true;
    header_bytes_ = 0;
  }
  void headers_complete() { in_headers_ = false; }

  bool is_readable() const override {
    return wait_for(fd_, POLLIN, ms_until(deadline(), seconds(limits_.idle_timeout_seconds)));
  }
  bool is_writable() const override {
    return wait_for(fd_, POLLOUT,
                    ms_until(request_deadline_, seconds(limits_.idle_timeout_seconds)));
  }

  ssize_t read(char* ptr, size_t size) override {
    if (offset_ == filled_) {
      if (!is_readable()) return -1;
      ssize_t n;
      do {
        n = ::recv(fd_, buffer_.data(), buffer_.size(), 0);
      } while (n < 0 && errno == EINTR);
      if (n <= 0) return -1;
      offset_ = 0;
      filled_ = static_cast<std::size_t>(n);
    }
    const std::size_t n = std::min(size, filled_ - offset_);
    if (in_headers_ && (header_bytes_ += n) > limits_.max_header_bytes) return -1;
    std::memcpy(ptr, buffer_.data() + offset_, n);
    offset_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (!is_writable()) return -1;
    ssize_t n;
    do {
      n = ::send(fd_, ptr, size, MSG_NOSIGNAL);
    } while (n < 0 && errno == EINTR);
    return n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    address_of(fd_, true, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    address_of(fd_, false, ip, port);
  }
  socket_t socket() const override { return fd_; }

  // Bytes already received beyond the current request (a pipelined next request).
  bool has_buffered() const { return offset_ < filled_; }

 private:
  Clock::time_point deadline() const {
    return in_headers_ ? std::min(header_deadline_, request_deadline_) : request_deadline_;
  }

  int fd_;
  const ConnectionLimits& limits_;
  Clock::time_point header_deadline_{}, request_deadline_{};
  bool in_headers_ = true;
  std::size_t header_bytes_ = 0;
  std::array<char, 4096> buffer_{};
  std::size_t offset_ = 0, filled_ = 0;
};

struct Connection {
  DeadlineStream* stream = nullptr;
  bool close_after = false;
};
thread_local Connection* current = nullptr;

// Handler threads started on demand up to a maximum; beyond min_threads, a thread idle for
// a minute ends.
class GrowingPool final : public httplib::TaskQueue {
 public:
  GrowingPool(int max_threads, int min_threads) : max_(max_threads), min_(min_threads) {}

  void enqueue(std::function<void()> fn) override {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(fn));
    if (jobs_.size() > static_cast<std::size_t>(idle_) && live_ < max_) {
      ++live_;
      std::thread([this] { run(); }).detach();
    }
    wake_.notify_one();
  }

  void shutdown() override {
    std::unique_lock lock(mutex_);
    stop_ = true;
    wake_.notify_all();
    done_.wait(lock, [this] { return live_ == 0; });
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    for (;;) {
      ++idle_;
      const bool woken = wake_.wait_for(lock, std::chrono::seconds(60),
                                        [this] { return stop_ || !jobs_.empty(); });
      --idle_;
      if (!jobs_.empty()) {
        auto fn = std::move(jobs_.front());
        jobs_.pop_front();
        lock.unlock();
        fn();
        lock.lock();
        continue;
      }
      if (stop_ || (!woken && live_ > min_)) break;
    }
    if (--live_ == 0) done_.notify_all();
  }

  const int max_, min_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::function<void()>> jobs_;
  int live_ = 0, idle_ = 0;
  bool stop_ = false;
};

// Answers a refused request, then reads (and drops) what the client still sends for a short
// while, so that a client writing its whole body before it reads sees the answer instead of a
// reset; bounded in time and bytes.
void drain_and_close(int fd) {
  ::shutdown(fd, SHUT_WR);
  const auto until = Clock::now() + std::chrono::seconds(2);
  std::array<char, 16384> sink;
  std::size_t total = 0;
  while (total < (64u << 20) && wait_for(fd, POLLIN, ms_until(until, std::chrono::seconds(2)))) {
    const ssize_t n = ::recv(fd, sink.data(), sink.size(), 0);
    if (n <= 0) break;
    total += static_cast<std::size_t>(n);
  }
  ::close(fd);
}

}  // namespace

HttpServer::HttpServer(ConnectionLimits limits) : limits_(limits) {
  const int threads = std::max(1, limits_.max_threads);
  new_task_queue = [threads] { return new GrowingPool(threads, std::min(threads, 4)); };
  set_tcp_nodelay(true);
  set_keep_alive_timeout(static_cast<time_t>(limits_.keep_alive_seconds));
  // SO_REUSEADDR lets a restarted server bind while old connections linger in TIME_WAIT;
  // without SO_REUSEPORT (cpp-httplib's default), a port in use is an error.
  set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
}

bool HttpServer::listen_after_bind() {
  // listen() again on the listening socket sets its backlog (Linux).
  const socket_t sock = svr_sock_;
  if (sock != INVALID_SOCKET && ::listen(sock, limits_.listen_backlog) != 0) return false;
  return httplib::Server::listen_after_bind();
}

void HttpServer::headers_complete() {
  if (current && current->stream) current->stream->headers_complete();
}

void HttpServer::close_after_response() {
  if (current) current->close_after = true;
}

bool HttpServer::process_and_close_socket(socket_t sock) {
  int yes = 1;
  ::setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  DeadlineStream stream(sock, limits_);
  Connection connection{&stream, false};
  current = &connection;
  bool ok = true;
  for (std::size_t count = keep_alive_max_count_; count > 0; --count) {
    // Wait for the next request in slices, so that a stopping server is noticed.
    const auto idle_until = Clock::now() + seconds(limits_.keep_alive_seconds);
    bool ready = stream.has_buffered();
    while (!ready && svr_sock_ != INVALID_SOCKET) {
      const int left = ms_until(idle_until, std::chrono::milliseconds(100));
      if (left <= 0) break;
      ready = wait_for(sock, POLLIN, left);
    }
    if (!ready || svr_sock_ == INVALID_SOCKET) break;
    stream.start_request();
    bool connection_closed = false;
    ok = process_request(stream, count == 1, connection_closed, nullptr);
    if (!ok || connection_closed || connection.close_after) break;
  }
  current = nullptr;
  if (connection.close_after) {
    drain_and_close(sock);
  } else {
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  }
  return ok;
}

}  // namespace compaction::server

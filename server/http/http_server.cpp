#include "http/http_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>

namespace compaction::server {

namespace {

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

// A handler's view of its connection: first the bytes the front buffered, then the socket,
// every wait at most the idle timeout and never past the request's deadline; reads beyond the
// buffer (a large body) and writes keep the front's pace rule.
class DeadlineStream final : public httplib::Stream {
 public:
  DeadlineStream(Connection& c, const ConnectionLimits& limits)
      : c_(c), limits_(limits), start_(Clock::now()) {}

  bool is_readable() const override {
    if (offset_ < c_.in.size()) return true;
    return wait_for(c_.fd, POLLIN, ms_until(read_deadline(), idle()));
  }
  bool is_writable() const override {
    return wait_for(c_.fd, POLLOUT, ms_until(write_deadline(), idle()));
  }

  ssize_t read(char* ptr, size_t size) override {
    if (offset_ == c_.in.size()) {
      // The buffer is used up: refill it from the socket.
      c_.in.clear();
      offset_ = 0;
      std::array<char, 16384> chunk;
      for (;;) {
        if (!is_readable()) return -1;
        const ssize_t n = ::recv(c_.fd, chunk.data(), chunk.size(), 0);
        if (n > 0) {
          c_.in.append(chunk.data(), static_cast<std::size_t>(n));
          from_socket_ += static_cast<std::size_t>(n);
          break;
        }
        if (n == 0) return -1;
        if (errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK) return -1;
      }
    }
    const std::size_t n = std::min(size, c_.in.size() - offset_);
    std::memcpy(ptr, c_.in.data() + offset_, n);
    offset_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    // The answer's pace counts from its first byte, not from the request: a handler may work
    // for long (an import waits for the one before it) before it answers.
    if (!writing_) write_start_ = Clock::now(), writing_ = true;
    for (;;) {
      if (!is_writable()) return -1;
      const ssize_t n = ::send(c_.fd, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n > 0) {
        written_ += static_cast<std::size_t>(n);
        return n;
      }
      if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
      return -1;
    }
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    address_of(c_.fd, true, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    address_of(c_.fd, false, ip, port);
  }
  socket_t socket() const override { return c_.fd; }

  // Leaves in the connection's buffer only what the client sent beyond the request.
  void keep_unread() { c_.in.erase(0, offset_); }

 private:
  Clock::duration idle() const { return seconds(limits_.idle_timeout_seconds); }
  Clock::time_point read_deadline() const {
    return paced_deadline(start_, from_socket_, limits_, c_.request_deadline);
  }
  Clock::time_point write_deadline() const {
    return paced_deadline(writing_ ? write_start_ : Clock::now(), written_, limits_,
                          c_.request_deadline + seconds(limits_.body_grace_seconds));
  }

  Connection& c_;
  const ConnectionLimits& limits_;
  Clock::time_point start_;
  std::size_t offset_ = 0;       // into c_.in
  std::size_t from_socket_ = 0;  // bytes the handler read from the socket itself
  std::size_t written_ = 0;
  bool writing_ = false;
  Clock::time_point write_start_{};
};

thread_local bool close_after = false;

// cpp-httplib's listener runs each accepted socket's task at once, on its own thread: the task
// (process_and_close_socket) only hands the socket to the front.
class InlineQueue final : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

// Raises the soft limit of open files to the hard one: every connection is a file.
int open_file_limit() {
  rlimit r{};
  if (::getrlimit(RLIMIT_NOFILE, &r) != 0) return 1024;
  if (r.rlim_cur < r.rlim_max) {
    r.rlim_cur = r.rlim_max;
    ::setrlimit(RLIMIT_NOFILE, &r);
    ::getrlimit(RLIMIT_NOFILE, &r);
  }
  return r.rlim_cur > 1u << 30 ? 1 << 30 : static_cast<int>(r.rlim_cur);
}

}  // namespace

// Handler threads started on demand up to a maximum; beyond min_threads, a thread idle for
// a minute ends. Every task queued before shutdown() runs.
class HandlerPool {
 public:
  HandlerPool(int max_threads, int min_threads) : max_(max_threads), min_(min_threads) {}

  void enqueue(std::function<void()> fn) {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(fn));
    if (jobs_.size() > static_cast<std::size_t>(idle_) && live_ < max_) {
      ++live_;
      std::thread([this] { run(); }).detach();
    }
    wake_.notify_one();
  }

  void shutdown() {
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

HttpServer::HttpServer(ConnectionLimits limits) : limits_(limits) {
  limits_.max_threads = std::max(1, limits_.max_threads);
  limits_.upload_slots = std::clamp(limits_.upload_slots, 1, limits_.max_threads);
  // Every connection is a file; keep some for the database, the artifacts and the logs.
  limits_.max_connections = std::max(16, std::min(limits_.max_connections, open_file_limit() - 256));
  new_task_queue = [] { return new InlineQueue(); };
  set_tcp_nodelay(true);
  // SO_REUSEADDR lets a restarted server bind while old connections linger in TIME_WAIT;
  // without SO_REUSEPORT (cpp-httplib's default), a port in use is an error.
  set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
}

HttpServer::~HttpServer() = default;

bool HttpServer::listen_after_bind() {
  // listen() again on the listening socket sets its backlog (Linux).
  const socket_t sock = svr_sock_;
  if (sock != INVALID_SOCKET && ::listen(sock, limits_.listen_backlog) != 0) return false;
  pool_ = std::make_unique<HandlerPool>(limits_.max_threads, std::min(limits_.max_threads, 4));
  auto check = head_check_ ? head_check_ : [](const RequestHead&) -> std::optional<ApiError> {
    return std::nullopt;
  };
  auto refused = refusal_logger_ ? refusal_logger_
                                 : [](const std::string&, const std::string&, const ApiError&) {};
  front_ = std::make_unique<ConnectionFront>(
      limits_, std::move(check),
      [this](std::unique_ptr<Connection> c, bool large) {
        Connection* raw = c.release();
        pool_->enqueue([this, raw, large] { serve(std::unique_ptr<Connection>(raw), large); });
      },
      std::move(refused));
  front_->start();
  const bool ok = httplib::Server::listen_after_bind();
  front_->stop();
  pool_->shutdown();
  return ok;
}

void HttpServer::close_after_response() { close_after = true; }

bool HttpServer::process_and_close_socket(socket_t sock) {
  front_->adopt(sock);
  return true;
}

void HttpServer::serve(std::unique_ptr<Connection> c, bool large) {
  close_after = false;
  bool ok = false, connection_closed = false;
  const bool last = static_cast<std::size_t>(c->served + 1) >= keep_alive_max_count_;
  {
    DeadlineStream stream(*c, limits_);
    ok = process_request(stream, last, connection_closed, nullptr);
    stream.keep_unread();
  }
  ++c->served;
  if (large) front_->upload_done();
  // After a final answer (or a large body a handler refused, partly unread) the connection
  // closes after a short drain: what the client still sends is never parsed as a request.
  const bool keep = ok && !connection_closed && !last && !close_after;
  front_->give_back(std::move(c), !keep);
}

}  // namespace compaction::server

// The whole REST API in process for the route tests: a real SQLite file in a temporary folder,
// every route registered as compaction-server registers them, HTTP on a loopback port and a
// client. A test's fixture derives from it and changes the server's options or App before it
// starts (configure_options, configure_app).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "compaction/result.hpp"
#include "http/http_server.hpp"
#include "routes/app.hpp"
#include "temp_dir.hpp"

namespace compaction::server {

struct LoopbackApi : ::testing::Test {
  static inline const std::string submit = "submit-secret";
  static inline const std::string worker = "worker-secret";

  TempDir dir;
  std::unique_ptr<Store> store;
  std::unique_ptr<App> app;
  HttpServer server;
  std::thread thread;
  std::unique_ptr<httplib::Client> client;

  // Called before the server starts: more tokens, other limits.
  virtual void configure_options(ServerOptions&) {}
  virtual void configure_app(App&) {}

  void SetUp() override {
    StoreConfig c;
    c.engine_version = compaction::engine_version();
    store = std::make_unique<Store>(dir.file("api.db"), c);
    ServerOptions o;
    o.tokens.add({TokenKind::submit, "", submit}, false);
    o.tokens.add({TokenKind::worker, "", worker}, false);
    o.web_dir = "";
    configure_options(o);
    app = std::unique_ptr<App>(new App{*store, o, {}, {}, {}, {}, {}});
    configure_app(*app);
    register_all_routes(server, *app);
    const int port = server.bind_to_any_port("127.0.0.1");
    ASSERT_GT(port, 0);
    thread = std::thread([this] { server.listen_after_bind(); });
    // stop() before the listener runs would be lost and TearDown would wait forever.
    while (!server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    client = std::make_unique<httplib::Client>("127.0.0.1", port);
    client->set_read_timeout(10, 0);
  }
  void TearDown() override {
    server.stop();
    if (thread.joinable()) thread.join();
  }

  static httplib::Headers auth(const std::string& token) {
    return {{"Authorization", "Bearer " + token}};
  }
  httplib::Result post(const std::string& path, const std::string& body, const std::string& token) {
    return client->Post(path.c_str(), auth(token), body, "application/json");
  }
};

}  // namespace compaction::server

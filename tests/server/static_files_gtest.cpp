// The dashboard's static files on a loopback port: each answer carries a tag of its content and
// "Cache-Control: no-cache"; a request naming the current tag gets 304 without a body, a file
// changed on disk gets a new tag and its new content, and a path outside the folder is not served.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "loopback_api.hpp"

using namespace compaction::server;

namespace {

struct StaticFiles : LoopbackApi {
  TempDir web;

  void write(const std::string& name, const std::string& text) {
    std::ofstream(web.file(name), std::ios::binary) << text;
  }
  void configure_options(ServerOptions& o) override {
    std::filesystem::create_directories(web.path / "js");
    write("index.html", "<!doctype html><title>t</title>");
    write("js/main.js", "export const a = 1;\n");
    o.web_dir = web.path.string();
  }
  httplib::Result get(const std::string& path, const std::string& if_none_match = "") {
    httplib::Headers h;
    if (!if_none_match.empty()) h.emplace("If-None-Match", if_none_match);
    return client->Get(path.c_str(), h);
  }
};

TEST_F(StaticFiles, ATaggedFileIsRevalidatedAndAnswered304WhileUnchanged) {
  auto first = get("/js/main.js");
  ASSERT_TRUE(first);
  EXPECT_EQ(first->status, 200);
  EXPECT_EQ(first->body, "export const a = 1;\n");
  EXPECT_EQ(first->get_header_value("Cache-Control"), "no-cache");
  const std::string tag = first->get_header_value("ETag");
  ASSERT_FALSE(tag.empty());
  EXPECT_EQ(tag.front(), '"');
  EXPECT_EQ(tag.back(), '"');

  auto again = get("/js/main.js", tag);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
  EXPECT_TRUE(again->body.empty());
  EXPECT_EQ(again->get_header_value("ETag"), tag);
  // A list of tags, one of them current, and a weak form of it name the file as well.
  EXPECT_EQ(get("/js/main.js", "\"other\", " + tag)->status, 304);
  EXPECT_EQ(get("/js/main.js", "W/" + tag)->status, 304);

  // Another file's tag, or the tag of an older content, gets the file.
  const std::string index_tag = get("/index.html")->get_header_value("ETag");
  EXPECT_NE(index_tag, tag);
  EXPECT_EQ(get("/js/main.js", index_tag)->status, 200);
  write("js/main.js", "export const a = 2;\n");
  auto changed = get("/js/main.js", tag);
  ASSERT_TRUE(changed);
  EXPECT_EQ(changed->status, 200);
  EXPECT_EQ(changed->body, "export const a = 2;\n");
  EXPECT_NE(changed->get_header_value("ETag"), tag);
}

TEST_F(StaticFiles, TheFolderIsTheLimit) {
  EXPECT_EQ(get("/")->status, 200);  // index.html
  EXPECT_EQ(get("/js/none.js")->status, 404);
  auto outside = get("/../api.db");
  ASSERT_TRUE(outside);
  EXPECT_NE(outside->status, 200);
}

}  // namespace

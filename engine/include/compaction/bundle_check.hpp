// Whether bytes are a well-formed file of a result bundle (schema/bundle-format.md), judged by
// the file's name, without trusting anything the file says of itself: a service checks each
// file of an upload with it before it stores and serves it.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace compaction {

// What is wrong with the file, or nothing:
//  .npy   NumPy 1.x, '<f4' in C order, 1 to 8 dimensions, its data exactly the shape's product
//         of float32 (a header's claim is checked against the bytes, never allocated);
//  .csv   UTF-8 text without NUL or other control characters but line ends; every line has the
//         header's number of fields; after the header, every field is a number (or nan, inf);
//  .png   the PNG signature, then chunks whose lengths walk exactly to an IEND chunk;
//  .bin   a movie (compaction/movie.hpp) whose header fits the file's size;
//  .json  one JSON document;
//  other  a name this format does not have.
std::optional<std::string> bundle_file_problem(const std::string& name, std::string_view bytes);

}  // namespace compaction

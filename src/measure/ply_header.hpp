// The header of a PLY file (Turk 1994, "The PLY Polygon File Format";
// paulbourke.net/dataformats/ply): what ply.cpp's body readers walk.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::measure::ply {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };
std::size_t size_of(Type t);
bool is_integral(Type t);

struct Property {
  std::string name;
  Type type = Type::f32;  // of the value, or of a list's items
  bool list = false;
  Type count_type = Type::u8;  // a list's length
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
};

enum class Format { ascii, binary_le, binary_be };

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::size_t vertex = 0;                  // index of the vertex element
  std::size_t xyz[3] = {0, 0, 0};          // indices of its x, y, z properties
  std::size_t data_begin = 0;              // first byte after end_header's line end
  std::uint32_t data_line = 0;             // first line after end_header
};

// Reads and checks the header of `bytes`: 'ply' first, one format line, then
// elements and their properties, up to end_header. One vertex element with
// scalar x, y, z properties; every element with a property. Located errors.
Header read_header(const std::string& bytes, const std::string& file);

}  // namespace deflex::measure::ply

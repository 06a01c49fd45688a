#include "geometry/ply.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cstring>
#include <limits>
#include <sstream>

#include "core/errors.hpp"

namespace bakesim {

const PlyProperty* PlyElement::find(const std::string& property) const {
  for (const auto& p : properties)
    if (p.name == property) return &p;
  return nullptr;
}

const PlyElement* PlyData::find(const std::string& element) const {
  for (const auto& e : elements)
    if (e.name == element) return &e;
  return nullptr;
}

namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

bool parse_type(const std::string& s, Type& t) {
  if (s == "char" || s == "int8")
    t = Type::i8;
  else if (s == "uchar" || s == "uint8")
    t = Type::u8;
  else if (s == "short" || s == "int16")
    t = Type::i16;
  else if (s == "ushort" || s == "uint16")
    t = Type::u16;
  else if (s == "int" || s == "int32")
    t = Type::i32;
  else if (s == "uint" || s == "uint32")
    t = Type::u32;
  else if (s == "float" || s == "float32")
    t = Type::f32;
  else if (s == "double" || s == "float64")
    t = Type::f64;
  else
    return false;
  return true;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8: return 1;
    case Type::i16:
    case Type::u16: return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32: return 4;
    case Type::f64: return 8;
  }
  return 1;
}

struct PropertyLayout {
  Type type = Type::f32;
  bool list = false;
  Type count_type = Type::u8;
};

// Sequential reader over either encoding.
class Cursor {
 public:
  Cursor(std::string_view bytes, bool ascii, bool big_endian, const std::string& where)
      : b_(bytes), ascii_(ascii), swap_(big_endian != (std::endian::native == std::endian::big)), where_(where) {}

  double read(Type t) {
    if (ascii_) return read_ascii();
    const std::size_t n = type_size(t);
    if (pos_ + n > b_.size()) fail("the file ends inside the data");
    char p[8];
    std::memcpy(p, b_.data() + pos_, n);
    if (swap_) std::reverse(p, p + n);
    pos_ += n;
    switch (t) {
      case Type::i8: {
        std::int8_t v;
        std::memcpy(&v, p, 1);
        return v;
      }
      case Type::u8: {
        std::uint8_t v;
        std::memcpy(&v, p, 1);
        return v;
      }
      case Type::i16: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case Type::u16: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case Type::i32: {
        std::int32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case Type::u32: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case Type::f32: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case Type::f64: {
        double v;
        std::memcpy(&v, p, 8);
        return v;
      }
    }
    return 0;
  }
  std::size_t remaining() const { return b_.size() - pos_; }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(where_, what); }

 private:
  double read_ascii() {
    while (pos_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
    const char* first = b_.data() + pos_;
    const char* last = b_.data() + b_.size();
    double v = 0;
    const auto r = std::from_chars(first, last, v);
    if (r.ec != std::errc() || r.ptr == first) fail("a number was expected in the ASCII data");
    pos_ += std::size_t(r.ptr - first);
    return v;
  }
  std::string_view b_;
  std::size_t pos_ = 0;
  bool ascii_;
  bool swap_;  // the data's byte order differs from this machine's
  const std::string& where_;
};

}  // namespace

PlyData parse_ply(std::string_view bytes, const std::string& where) {
  const std::string_view end_marker = "end_header";
  const std::size_t end = bytes.find(end_marker);
  if (bytes.substr(0, 3) != "ply" || end == std::string_view::npos)
    throw InputError(where, "not a PLY file (no 'ply' magic or no end_header)");
  std::size_t data_start = end + end_marker.size();
  if (data_start < bytes.size() && bytes[data_start] == '\r') ++data_start;
  if (data_start < bytes.size() && bytes[data_start] == '\n') ++data_start;
  std::istringstream header{std::string(bytes.substr(0, end))};
  std::string line;
  bool ascii = false, big_endian = false, format_seen = false;
  PlyData ply;
  std::vector<std::vector<PropertyLayout>> layouts;
  std::getline(header, line);  // "ply"
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word) || word == "comment" || word == "obj_info") continue;
    if (word == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii")
        ascii = true;
      else if (f == "binary_big_endian")
        big_endian = true;
      else if (f != "binary_little_endian")
        throw InputError(where, "unknown PLY format '" + f + "' (ascii, binary_little_endian or binary_big_endian)");
      format_seen = true;
    } else if (word == "element") {
      PlyElement e;
      long long count = -1;
      if (!(ls >> e.name >> count) || count < 0) throw InputError(where, "bad element line '" + line + "'");
      e.count = std::size_t(count);
      ply.elements.push_back(std::move(e));
      layouts.emplace_back();
    } else if (word == "property") {
      if (ply.elements.empty()) throw InputError(where, "property before any element");
      PropertyLayout l;
      PlyProperty p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it;
        if (!parse_type(ct, l.count_type) || !parse_type(it, l.type))
          throw InputError(where, "bad list property '" + line + "'");
        l.list = p.is_list = true;
      } else if (!parse_type(t, l.type)) {
        throw InputError(where, "unknown property type in '" + line + "'");
      }
      if (!(ls >> p.name)) throw InputError(where, "property without a name: '" + line + "'");
      ply.elements.back().properties.push_back(std::move(p));
      layouts.back().push_back(l);
    } else {
      throw InputError(where, "unexpected header line '" + line + "'");
    }
  }
  if (!format_seen) throw InputError(where, "PLY header has no format line");
  Cursor cur(bytes.substr(data_start), ascii, big_endian, where);
  for (std::size_t e = 0; e < ply.elements.size(); ++e) {
    PlyElement& el = ply.elements[e];
    // Each item takes at least one byte per property: refuse counts the data cannot hold.
    const std::size_t min_item = std::max<std::size_t>(1, el.properties.size());
    if (el.count > cur.remaining() / min_item + 1)
      cur.fail(fmt::format("element '{}' claims {} items, more than the file holds", el.name, el.count));
    for (auto& p : el.properties) (p.is_list ? (void)p.lists.reserve(el.count) : p.values.reserve(el.count));
    for (std::size_t i = 0; i < el.count; ++i)
      for (std::size_t k = 0; k < el.properties.size(); ++k) {
        const PropertyLayout& l = layouts[e][k];
        PlyProperty& p = el.properties[k];
        if (!l.list) {
          p.values.push_back(cur.read(l.type));
          continue;
        }
        const double count = cur.read(l.count_type);
        if (!(count >= 0) || count > 1e6 || count > double(cur.remaining()))
          cur.fail("bad list length in element '" + el.name + "'");
        std::vector<std::uint32_t> list(static_cast<std::size_t>(count));
        for (auto& v : list) {
          const double x = cur.read(l.type);
          if (!(x >= 0) || x > double(std::numeric_limits<std::uint32_t>::max()))
            cur.fail("bad index in a list of element '" + el.name + "'");
          v = std::uint32_t(x);
        }
        p.lists.push_back(std::move(list));
      }
  }
  return ply;
}

}  // namespace bakesim

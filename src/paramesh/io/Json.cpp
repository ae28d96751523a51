// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Json.cpp
/// JSON serialisation and locale-independent number formatting.
#include "paramesh/io/Json.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>

#include <charconv>
#include <cmath>
#include <cstring>

#include "paramesh/util/Error.hpp"

#if !(defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L)
#include <locale>
#include <sstream>
#endif

namespace paramesh {

namespace io {

std::size_t formatDouble(double v, char* buf, int precision) {
  if (std::isnan(v)) { std::memcpy(buf, "nan", 3); return 3; }
  if (std::isinf(v)) {
    if (v < 0) { std::memcpy(buf, "-inf", 4); return 4; }
    std::memcpy(buf, "inf", 3);
    return 3;
  }
#if defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L
  char* end = buf + 32;
  std::to_chars_result r = precision > 0
                               ? std::to_chars(buf, end, v, std::chars_format::general, precision)
                               : std::to_chars(buf, end, v);
  return static_cast<std::size_t>(r.ptr - buf);
#else
  // Fallback for standard libraries without floating-point to_chars: slower but still exact.
  std::ostringstream os;
  os.imbue(std::locale::classic());
  if (precision > 0) {
    os.precision(precision);
    os << v;
  } else {
    std::string s;
    for (int p = 15; p <= 17; ++p) {  // shortest of 15..17 significant digits that round-trips
      std::ostringstream t;
      t.imbue(std::locale::classic());
      t.precision(p);
      t << v;
      s = t.str();
      std::istringstream in(s);
      in.imbue(std::locale::classic());
      double back = 0;
      in >> back;
      if (back == v) break;
    }
    os << s;
  }
  std::string s = os.str();
  std::memcpy(buf, s.data(), s.size());
  return s.size();
#endif
}

namespace {
/// Length of the valid UTF-8 sequence starting at s[i], or 0 when it is invalid.
std::size_t utf8Length(const std::string& s, std::size_t i) {
  auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  unsigned char c = byte(i);
  std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  uint32_t cp = n == 1 ? c : n == 2 ? (c & 0x1Fu) : n == 3 ? (c & 0x0Fu) : (c & 0x07u);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (byte(i + k) & 0x3Fu);
  }
  static const uint32_t minCp[5] = {0, 0, 0x80, 0x800, 0x10000};  // reject overlong forms
  if (cp < minCp[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}
}  // namespace

void appendJsonString(std::string& out, const std::string& s) {
  static const char* hex = "0123456789abcdef";
  out += '"';
  for (std::size_t i = 0; i < s.size();) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    switch (c) {
      case '"': out += "\\\""; ++i; continue;
      case '\\': out += "\\\\"; ++i; continue;
      case '\b': out += "\\b"; ++i; continue;
      case '\f': out += "\\f"; ++i; continue;
      case '\n': out += "\\n"; ++i; continue;
      case '\r': out += "\\r"; ++i; continue;
      case '\t': out += "\\t"; ++i; continue;
      default: break;
    }
    if (c < 0x20) {
      out += "\\u00";
      out += hex[c >> 4];
      out += hex[c & 0xF];
      ++i;
      continue;
    }
    std::size_t n = utf8Length(s, i);
    if (n == 0) {  // invalid UTF-8 byte: replacement character, so the output stays valid JSON
      out += "\\ufffd";
      ++i;
      continue;
    }
    out.append(s, i, n);
    i += n;
  }
  out += '"';
}

}  // namespace io

Json& Json::operator[](const std::string& key) {
  if (type_ == Type::Null) type_ = Type::Object;
  if (type_ != Type::Object) throw Error("Json: operator[\"" + key + "\"] on a non-object value");
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return items_[i];
  keys_.push_back(key);
  items_.emplace_back();
  return items_.back();
}

const Json& Json::at(const std::string& key) const {
  if (type_ == Type::Object)
    for (std::size_t i = 0; i < keys_.size(); ++i)
      if (keys_[i] == key) return items_[i];
  throw Error("Json: no member \"" + key + "\"");
}

const Json& Json::at(std::size_t i) const {
  if (type_ != Type::Array || i >= items_.size())
    throw Error("Json: array index " + std::to_string(i) + " out of range");
  return items_[i];
}

bool Json::contains(const std::string& key) const {
  if (type_ != Type::Object) return false;
  for (const std::string& k : keys_)
    if (k == key) return true;
  return false;
}

Json& Json::push(Json v) {
  if (type_ == Type::Null) type_ = Type::Array;
  if (type_ != Type::Array) throw Error("Json: push on a non-array value");
  items_.push_back(std::move(v));
  return items_.back();
}

std::size_t Json::size() const {
  return (type_ == Type::Array || type_ == Type::Object) ? items_.size() : 0;
}

std::string Json::dump(int indent) const {
  std::string out;
  write(out, indent, 0);
  return out;
}

void Json::write(std::string& out, int indent, int level) const {
  auto newline = [&](int lvl) {
    if (indent <= 0) return;
    out += '\n';
    out.append(static_cast<std::size_t>(indent) * static_cast<std::size_t>(lvl), ' ');
  };
  char buf[40];
  switch (type_) {
    case Type::Null: out += "null"; return;
    case Type::Bool: out += bool_ ? "true" : "false"; return;
    case Type::Int: {
      std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, int_);
      out.append(buf, r.ptr);
      return;
    }
    case Type::Double:
      if (!std::isfinite(double_)) {
        out += "null";
      } else {
        out.append(buf, io::formatDouble(double_, buf, 0));
      }
      return;
    case Type::String: io::appendJsonString(out, string_); return;
    case Type::Array:
    case Type::Object: {
      bool obj = type_ == Type::Object;
      out += obj ? '{' : '[';
      if (items_.empty()) {
        out += obj ? '}' : ']';
        return;
      }
      for (std::size_t i = 0; i < items_.size(); ++i) {
        if (i) out += ',';
        newline(level + 1);
        if (obj) {
          io::appendJsonString(out, keys_[i]);
          out += indent > 0 ? ": " : ":";
        }
        items_[i].write(out, indent, level + 1);
      }
      newline(level);
      out += obj ? '}' : ']';
      return;
    }
  }
}

double Json::number() const {
  if (type_ == Type::Int) return static_cast<double>(int_);
  if (type_ == Type::Double) return double_;
  throw Error("JSON: expected a number");
}

bool Json::boolean() const {
  if (type_ != Type::Bool) throw Error("JSON: expected true or false");
  return bool_;
}

const std::string& Json::str() const {
  if (type_ != Type::String) throw Error("JSON: expected a string");
  return string_;
}

namespace {
class JsonParser {
 public:
  explicit JsonParser(const std::string& t) : s_(t) {}
  Json parseAll() {
    Json v = value();
    ws();
    if (i_ != s_.size()) fail("unexpected text after the value");
    return v;
  }

 private:
  const std::string& s_;
  size_t i_ = 0;
  static int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }
  [[noreturn]] void fail(const std::string& what) const {
    size_t line = 1, col = 1;
    for (size_t k = 0; k < i_ && k < s_.size(); ++k) {
      if (s_[k] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw Error("JSON: " + what + " at line " + std::to_string(line) + ", column " + std::to_string(col));
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  bool eat(char c) {
    ws();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!eat(c)) fail(std::string("expected '") + c + "'");
  }
  Json value() {
    ws();
    if (i_ >= s_.size()) fail("unexpected end of text");
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      Json o = Json::object();
      if (eat('}')) return o;
      do {
        ws();
        if (i_ >= s_.size() || s_[i_] != '"') fail("expected a key string");
        std::string k = string();
        expect(':');
        o[k] = value();
      } while (eat(','));
      expect('}');
      return o;
    }
    if (c == '[') {
      ++i_;
      Json a = Json::array();
      if (eat(']')) return a;
      do {
        a.push(value());
      } while (eat(','));
      expect(']');
      return a;
    }
    if (c == '"') return Json(string());
    if (s_.compare(i_, 4, "true") == 0) {
      i_ += 4;
      return Json(true);
    }
    if (s_.compare(i_, 5, "false") == 0) {
      i_ += 5;
      return Json(false);
    }
    if (s_.compare(i_, 4, "null") == 0) {
      i_ += 4;
      return Json();
    }
    return numberValue();
  }
  std::string string() {
    ++i_;  // opening quote
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c == '\\') {
        if (i_ >= s_.size()) fail("bad escape");
        const char e = s_[i_++];
        switch (e) {
          case 'n': out += '\n'; break;
          case 't': out += '\t'; break;
          case 'r': out += '\r'; break;
          case 'b': out += '\b'; break;
          case 'f': out += '\f'; break;
          case 'u': {
            // exactly four hex digits (std::stoul would also take "+1", " 1f", "0x1" and throw
            // std::invalid_argument on none)
            unsigned cp = 0;
            for (int k = 0; k < 4; ++k, ++i_) {
              const int d = i_ < s_.size() ? hexDigit(s_[i_]) : -1;
              if (d < 0) fail("bad \\u escape (\\u needs four hex digits)");
              cp = cp * 16 + (unsigned)d;
            }
            if (cp < 0x80) {
              out += (char)cp;
            } else if (cp < 0x800) {
              out += (char)(0xC0 | (cp >> 6));
              out += (char)(0x80 | (cp & 0x3F));
            } else {
              out += (char)(0xE0 | (cp >> 12));
              out += (char)(0x80 | ((cp >> 6) & 0x3F));
              out += (char)(0x80 | (cp & 0x3F));
            }
            break;
          }
          default: out += e;
        }
      } else {
        out += c;
      }
    }
    if (i_ >= s_.size()) fail("unterminated string");
    ++i_;
    return out;
  }
  Json numberValue() {
    const size_t start = i_;
    if (s_[i_] == '-') ++i_;
    bool isInt = true;
    while (i_ < s_.size() && (std::isdigit((unsigned char)s_[i_]) || s_[i_] == '.' || s_[i_] == 'e' ||
                              s_[i_] == 'E' || s_[i_] == '+' || s_[i_] == '-')) {
      if (!std::isdigit((unsigned char)s_[i_])) isInt = false;
      ++i_;
    }
    const std::string tok = s_.substr(start, i_ - start);
    if (tok.empty() || tok == "-") fail("expected a value");
    char* end = nullptr;
    if (isInt) {
      errno = 0;
      const long long v = std::strtoll(tok.c_str(), &end, 10);
      if (*end) fail("bad number '" + tok + "'");
      // beyond int64 (strtoll would clamp it to LLONG_MAX silently): read it as a double
      if (errno != ERANGE) return Json((int64_t)v);
    }
    const double v = std::strtod(tok.c_str(), &end);
    if (*end) fail("bad number '" + tok + "'");
    return Json(v);
  }
};
}  // namespace

Json Json::parse(const std::string& text) { return JsonParser(text).parseAll(); }

}  // namespace paramesh

// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Json.hpp
/// A tiny JSON value and writer (no parser): null, bool, integer, double, string, array and
/// object with insertion-ordered keys. Used for run reports and statistics.
///
///   Json j = Json::object();
///   j["faces"] = 6;
///   j["sizes"].push(Json(0.5));     // a null value becomes an array on push
///   j["name"] = "box";
///   std::string text = j.dump(2);  // 2-space indentation; dump() is compact
///
/// Doubles are written in the shortest form that reads back exactly; NaN and infinities are
/// written as null (JSON has no representation for them). Output is locale-independent.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace paramesh {

class Json {
 public:
  enum class Type { Null, Bool, Int, Double, String, Array, Object };

  Json() = default;  ///< null
  Json(std::nullptr_t) {}
  Json(bool b) : type_(Type::Bool), bool_(b) {}
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  Json(T v) {
    if constexpr (std::is_unsigned_v<T> && sizeof(T) >= sizeof(int64_t)) {
      if (v > static_cast<T>(INT64_MAX)) {  // does not fit an int64: keep the magnitude
        type_ = Type::Double;
        double_ = static_cast<double>(v);
        return;
      }
    }
    type_ = Type::Int;
    int_ = static_cast<int64_t>(v);
  }
  template <class T, std::enable_if_t<std::is_floating_point_v<T>, int> = 0>
  Json(T v) : type_(Type::Double), double_(static_cast<double>(v)) {}
  Json(const char* s) : type_(Type::String), string_(s ? s : "") {}
  Json(std::string s) : type_(Type::String), string_(std::move(s)) {}

  static Json object() { Json j; j.type_ = Type::Object; return j; }
  static Json array() { Json j; j.type_ = Type::Array; return j; }

  Type type() const { return type_; }
  bool isNull() const { return type_ == Type::Null; }
  bool isObject() const { return type_ == Type::Object; }
  bool isArray() const { return type_ == Type::Array; }

  /// Object member, inserted (as null) at the end when missing. A null value becomes an empty
  /// object first; any other non-object type throws paramesh::Error.
  Json& operator[](const std::string& key);
  /// Existing object member; throws paramesh::Error when absent or not an object.
  const Json& at(const std::string& key) const;
  /// Array element; throws paramesh::Error when out of range or not an array.
  const Json& at(std::size_t i) const;
  bool contains(const std::string& key) const;
  /// Value accessors; each throws paramesh::Error when the type does not match (numbers convert).
  double number() const;
  bool boolean() const;
  const std::string& str() const;
  /// Parses JSON text; throws paramesh::Error with the position on malformed input.
  static Json parse(const std::string& text);
  /// Appends to an array and returns the new element. A null value becomes an empty array
  /// first; any other non-array type throws paramesh::Error.
  Json& push(Json v);
  /// Number of elements (array) or members (object); 0 otherwise.
  std::size_t size() const;
  /// Keys of an object in insertion order (empty for other types).
  const std::vector<std::string>& keys() const { return keys_; }

  /// Serialises the value. indent <= 0: compact on one line; indent > 0: one member/element per
  /// line, nested levels indented by that many spaces.
  std::string dump(int indent = 0) const;

 private:
  void write(std::string& out, int indent, int level) const;

  Type type_ = Type::Null;
  bool bool_ = false;
  int64_t int_ = 0;
  double double_ = 0;
  std::string string_;
  std::vector<std::string> keys_;  ///< object keys, parallel to items_
  std::vector<Json> items_;        ///< array elements or object values
};

namespace io {
/// Writes v locale-independently into buf (at least 32 chars) and returns the length.
/// precision > 0: like printf("%.<precision>g"); precision <= 0: shortest exact round-trip form.
/// NaN and infinities are written as "nan", "inf", "-inf".
std::size_t formatDouble(double v, char* buf, int precision);
/// Appends the JSON string literal for s (quoted, escaped; invalid UTF-8 bytes are kept as is).
void appendJsonString(std::string& out, const std::string& s);
}  // namespace io

}  // namespace paramesh

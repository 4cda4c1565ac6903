#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace dxlemu::model {

/// One value of a JSON document with its JSON pointer and the document's origin at hand, so
/// that every refusal names exactly where the problem is: ModelError("FILE", "/pointer",
/// reason). The document and the origin must outlive the node.
class JsonNode {
 public:
  JsonNode(const nlohmann::json& value, std::string pointer, const std::string& origin)
      : value_(value), pointer_(std::move(pointer)), origin_(origin) {}

  /// Throws ModelError for this value.
  [[noreturn]] void fail(const std::string& reason) const;

  const std::string& pointer() const { return pointer_; }
  bool has(const char* key) const { return value_.contains(key); }
  bool is_string() const { return value_.is_string(); }
  bool is_integer() const { return value_.is_number_integer(); }

  /// The member `key`; refused when it is missing.
  JsonNode at(const char* key) const;
  /// The member `key`, which must exist (has()).
  JsonNode child(const char* key) const;
  /// The array element `index`, which must exist (array_size()).
  JsonNode at(std::size_t index) const;

  /// Refuses anything but an object whose members are all in `allowed`.
  void expect_object(std::span<const std::string_view> allowed) const;
  /// The array's length; refuses anything but an array.
  std::size_t array_size() const;
  std::string string() const;
  /// An integer within lo ~ hi.
  std::int64_t integer(std::int64_t lo, std::int64_t hi) const;
  double positive_number() const;
  bool boolean() const;
  /// An array of strings.
  std::vector<std::string> strings() const;

 private:
  const nlohmann::json& value_;
  std::string pointer_;
  const std::string& origin_;
};

}  // namespace dxlemu::model

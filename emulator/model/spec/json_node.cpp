#include "model/spec/json_node.hpp"

#include <algorithm>
#include <limits>

#include "model/spec/model_error.hpp"

namespace dxlemu::model {
namespace {

// RFC 6901: "~" and "/" in a key are written "~0" and "~1".
std::string escape(const std::string& key) {
  std::string out;
  for (const char c : key) {
    out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  }
  return out;
}

}  // namespace

void JsonNode::fail(const std::string& reason) const {
  throw ModelError(origin_, pointer_, reason);
}

JsonNode JsonNode::at(const char* key) const {
  if (!value_.contains(key)) {
    fail(std::string("missing required field \"") + key + "\"");
  }
  return child(key);
}

JsonNode JsonNode::child(const char* key) const {
  return JsonNode(value_.at(key), pointer_ + "/" + escape(key), origin_);
}

JsonNode JsonNode::at(std::size_t index) const {
  return JsonNode(value_.at(index), pointer_ + "/" + std::to_string(index), origin_);
}

void JsonNode::expect_object(std::span<const std::string_view> allowed) const {
  if (!value_.is_object()) {
    fail("must be an object");
  }
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    const std::string& key = it.key();
    const auto known = [&key](std::string_view a) { return key == a; };
    if (std::find_if(allowed.begin(), allowed.end(), known) == allowed.end()) {
      JsonNode(it.value(), pointer_ + "/" + escape(key), origin_).fail("unknown field");
    }
  }
}

std::size_t JsonNode::array_size() const {
  if (!value_.is_array()) {
    fail("must be an array");
  }
  return value_.size();
}

std::string JsonNode::string() const {
  if (!value_.is_string()) {
    fail("must be a string");
  }
  return value_.get<std::string>();
}

std::int64_t JsonNode::integer(std::int64_t lo, std::int64_t hi) const {
  if (!value_.is_number_integer()) {
    fail("must be an integer");
  }
  const auto v = value_.is_number_unsigned()
                     ? static_cast<std::int64_t>(std::min<std::uint64_t>(
                           value_.get<std::uint64_t>(),
                           static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())))
                     : value_.get<std::int64_t>();
  if (v < lo || v > hi) {
    fail("must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " +
         std::to_string(v));
  }
  return v;
}

double JsonNode::positive_number() const {
  if (!value_.is_number() || value_.get<double>() <= 0) {
    fail("must be a positive number");
  }
  return value_.get<double>();
}

bool JsonNode::boolean() const {
  if (!value_.is_boolean()) {
    fail("must be true or false");
  }
  return value_.get<bool>();
}

std::vector<std::string> JsonNode::strings() const {
  std::vector<std::string> out;
  for (std::size_t i = 0, n = array_size(); i < n; ++i) {
    out.push_back(at(i).string());
  }
  return out;
}

}  // namespace dxlemu::model

#pragma once

#include <stdexcept>
#include <string>

namespace dxlemu::model {

/// A model file the emulator refuses. what() reads "FILE: POINTER: REASON", e.g.
/// "models/xm430-w350.json: /items/12/size: must be 1, 2 or 4, got 3".
class ModelError : public std::runtime_error {
 public:
  /// `origin` names the file (or other source), `pointer` is an RFC 6901 JSON pointer ("" for the
  /// whole document), `reason` says what is wrong.
  ModelError(std::string origin, std::string pointer, std::string reason);

  const std::string& origin() const { return origin_; }
  const std::string& pointer() const { return pointer_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string origin_;
  std::string pointer_;
  std::string reason_;
};

}  // namespace dxlemu::model

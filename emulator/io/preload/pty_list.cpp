#include "io/preload/pty_list.hpp"

#include <cstring>

namespace dxlemu::preload {

PtyListError parse_pty_list(const char* text, PtyList& list) {
  list.count = 0;
  if (text == nullptr) {
    return PtyListError::None;
  }
  const std::size_t length = std::strlen(text);
  if (length >= kMaxPtyListBytes) {
    return PtyListError::TooLong;
  }
  std::memcpy(list.storage, text, length + 1);
  char* entry = list.storage;
  while (true) {
    char* colon = std::strchr(entry, ':');
    if (colon != nullptr) {
      *colon = '\0';
    }
    if (*entry != '\0') {
      // A relative path would name a different file for each working directory of the client.
      if (*entry != '/') {
        list.count = 0;
        return PtyListError::NotAbsolute;
      }
      if (list.count == kMaxPtyPaths) {
        list.count = 0;
        return PtyListError::TooMany;
      }
      list.paths[list.count++] = entry;
    }
    if (colon == nullptr) {
      return PtyListError::None;
    }
    entry = colon + 1;
  }
}

const char* pty_list_error_text(PtyListError error) {
  switch (error) {
    case PtyListError::None:
      return "";
    case PtyListError::TooLong:
      return "DXLEMU_PTYS is longer than 16383 bytes";
    case PtyListError::TooMany:
      return "DXLEMU_PTYS names more than 64 paths";
    case PtyListError::NotAbsolute:
      return "DXLEMU_PTYS names a relative path (every path must start with '/')";
  }
  return "";
}

}  // namespace dxlemu::preload

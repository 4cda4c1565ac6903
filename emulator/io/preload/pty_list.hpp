#pragma once

#include <cstddef>

namespace dxlemu::preload {

/// The most paths DXLEMU_PTYS may name: a bus config's ports, each with its PTY and its link.
inline constexpr std::size_t kMaxPtyPaths = 64;
/// The most bytes of DXLEMU_PTYS kept (the terminating NUL included).
inline constexpr std::size_t kMaxPtyListBytes = 16384;

/// The paths of DXLEMU_PTYS (docs/exec.md): a fixed-size copy, so that the preload library needs
/// no allocation and no constructor runs before main.
struct PtyList {
  char storage[kMaxPtyListBytes];   ///< the list, each ':' replaced by a NUL
  const char* paths[kMaxPtyPaths];  ///< into `storage`, in the order given
  std::size_t count;
};

/// Why a list was refused, for the one warning the preload library prints.
enum class PtyListError { None, TooLong, TooMany, NotAbsolute };

/// Splits `text` (colon-separated, empty entries skipped) into `list`. On an error `list` is left
/// empty: a list that cannot be read whole affects no descriptor rather than some of them.
/// `text` may be nullptr (the variable is not set): an empty list, no error.
PtyListError parse_pty_list(const char* text, PtyList& list);

/// A sentence naming the error, without a newline; "" for None.
const char* pty_list_error_text(PtyListError error);

}  // namespace dxlemu::preload

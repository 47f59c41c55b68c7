// Text that came from a user (keys, values, names, file paths) on its way into a message: control
// characters escaped so that a message cannot move the cursor, recolour or clear the terminal it
// is printed on, and file names checked for a NUL character, which would cut a path short where
// the system reads it. The bottom layer, so every layer's error formatting can use the one
// function.
#pragma once

#include <string>
#include <string_view>

namespace anamorph {

// `s` with every C0 control character (U+0000 to U+001F), DEL, every C1 control (U+0080 to
// U+009F) and every byte that is not part of well-formed UTF-8 written as an escape: \n, \r, \t,
// \xNN for the other bytes, \u0080 to \u009f for C1 controls. Other text, including
// backslashes, is kept as it is, so printable(printable(s)) == printable(s): a message escaped on
// its way up may be escaped again where it is printed.
std::string printable(std::string_view s);

// Whether a file name holds a NUL character (the system would read it only up to there).
inline bool has_nul(std::string_view path) { return path.find('\0') != std::string_view::npos; }

// "the file name 'a\x00b' contains a NUL character (the system would read it as 'a')"; without
// the name ("the file name contains ...") where the message names the file already.
std::string nul_in_path_message(std::string_view path, bool with_name = true);

}  // namespace anamorph

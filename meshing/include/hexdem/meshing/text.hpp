#pragma once
/// \file text.hpp
/// Quoting user text (names, strings from input files) in one-line messages.

#include <cstdio>
#include <string>
#include <string_view>

namespace hexdem::meshing {

/// `text` with every control character and backslash escaped (\n, \t, \r, \\, \xHH), so that
/// a message quoting it stays on one line and shows what the file holds.
inline std::string escape_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      case '\\': out += "\\\\"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\x%02X", c);
          out += buffer;
        } else {
          out += ch;
        }
    }
  }
  return out;
}

/// `message` with its control characters escaped as in escape_text (backslashes are kept
/// as they are: the parts of the message that quote user text are escaped already).
inline std::string one_line(std::string_view message) {
  std::string out;
  out.reserve(message.size());
  for (const char ch : message) {
    if (ch == '\\') {
      out += ch;
    } else {
      out += escape_text(std::string_view(&ch, 1));
    }
  }
  return out;
}

/// Whether `text` holds a control character (a NUL, a line break, ...).
inline bool has_control_character(std::string_view text) {
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) return true;
  }
  return false;
}

/// Whether `text` holds a character that would break a CSV header it is written into
/// unquoted (a comma or a double quote): body and boundary set names name CSV columns
/// (docs/outline-format.md, "Names").
inline bool has_csv_special(std::string_view text) {
  return text.find_first_of(",\"") != std::string_view::npos;
}

}  // namespace hexdem::meshing

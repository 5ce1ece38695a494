#pragma once
// Text from files in messages: control characters escaped (an ESC in a material name or a PFM header must not retitle
// or clear the user's terminal), and JSON errors in the project's words (the key, what was expected) rather than the
// JSON library's exception ids ("[json.exception.out_of_range.406]").

#include <nlohmann/json.hpp>

#include <cctype>
#include <cstdio>
#include <string>
#include <string_view>

namespace vplab {

namespace detail {
inline std::string escapeControls(std::string_view text, bool keepNewlines) {
  std::string out;
  out.reserve(text.size());
  for (unsigned char c : text) {
    if ((c >= 0x20 && c != 0x7f) || (keepNewlines && c == '\n')) {
      out += static_cast<char>(c);
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}
}  // namespace detail

/// `text` with every control byte (below 0x20, and 0x7f) written as \n, \t, \r or \xNN. Backslashes stay as they are,
/// so that escaping twice (a message built from escaped text, escaped again when printed) changes nothing. For text
/// from files and typed text, where it enters a message.
inline std::string printable(std::string_view text) { return detail::escapeControls(text, false); }

/// A whole message as printed: control bytes escaped as printable() does, except the line breaks, which are the
/// message's own (a list of choices, one per line); text from files and typed text in it is escaped where it entered.
inline std::string printableMessage(std::string_view text) { return detail::escapeControls(text, true); }

/// A number in a message, as printf's %g writes it (1e+07, 0.5).
inline std::string numberText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

/// The key whose value starts at byte `at` of a JSON text: the last "name": before it, or empty.
inline std::string jsonKeyBefore(std::string_view text, std::size_t at) {
  std::size_t colon = text.rfind(':', at);
  if (colon == std::string_view::npos) return {};
  std::size_t end = text.rfind('"', colon);
  if (end == std::string_view::npos || end == 0) return {};
  std::size_t begin = text.rfind('"', end - 1);
  if (begin == std::string_view::npos) return {};
  return std::string(text.substr(begin + 1, end - begin - 1));
}

/// Why `text` failed to parse as JSON, without the library's exception id: "the file is empty", "\"clampBound\": the
/// number 1e999 is out of range (beyond +-1.8e308)", "not valid JSON: syntax error at line 2, column 5: ...".
inline std::string describeJsonError(std::string_view text, const nlohmann::json::exception& e) {
  std::string what = e.what();
  if (what.rfind("[json.exception.", 0) == 0) {
    std::size_t close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
  }
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) return "the file is empty (expected a JSON object)";
  // nlohmann: "number overflow parsing '1e999'"
  const std::string overflow = "number overflow parsing '";
  if (what.rfind(overflow, 0) == 0) {
    std::string token = what.substr(overflow.size());
    if (!token.empty() && token.back() == '\'') token.pop_back();
    std::string key;
    if (std::size_t at = text.find(token); at != std::string_view::npos) key = jsonKeyBefore(text, at);
    return (key.empty() ? "" : "\"" + printable(key) + "\": ") + "the number " + printable(token) +
           " is out of range (beyond +-1.8e308)";
  }
  // "; last read: '...'" quotes raw bytes of the file (invalid UTF-8 among them), saying nothing the position does
  // not.
  if (std::size_t last = what.find("; last read: '"); last != std::string::npos) {
    std::size_t end = what.find("'; ", last + 14);
    what.erase(last, end == std::string::npos ? std::string::npos : end + 1 - last);
  }
  if (what.rfind("parse error", 0) == 0) what = "not valid JSON: " + what.substr(std::string("parse error ").size());
  if (what.size() > 200) what = what.substr(0, 200) + "...";
  return printable(what);
}

}  // namespace vplab

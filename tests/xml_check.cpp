#include "tests/xml_check.h"

#include <cctype>
#include <cstdint>
#include <functional>

namespace vplab {

namespace {

class Parser {
 public:
  explicit Parser(const std::string& s) : s_(s) {}

  XmlElement document() {
    if (s_.compare(0, 5, "<?xml") == 0) {
      std::size_t end = s_.find("?>");
      if (end == std::string::npos) fail("unterminated XML declaration");
      pos_ = end + 2;
    }
    skipMisc();
    if (pos_ >= s_.size() || s_[pos_] != '<') fail("no root element");
    XmlElement root = element();
    skipMisc();
    if (pos_ != s_.size()) fail("content after the root element");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    std::size_t line = 1;
    for (std::size_t i = 0; i < pos_ && i < s_.size(); ++i) line += s_[i] == '\n';
    throw XmlError("line " + std::to_string(line) + ": " + what);
  }

  bool startsWith(const char* t) const { return s_.compare(pos_, std::char_traits<char>::length(t), t) == 0; }

  void skipSpace() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }

  void comment() {
    std::size_t end = s_.find("-->", pos_ + 4);
    if (end == std::string::npos) fail("unterminated comment");
    pos_ = end + 3;
  }

  // Whitespace and comments around the root.
  void skipMisc() {
    for (;;) {
      skipSpace();
      if (startsWith("<!--"))
        comment();
      else
        return;
    }
  }

  static bool nameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':'; }
  static bool nameChar(char c) {
    return nameStart(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.';
  }

  std::string name() {
    if (pos_ >= s_.size() || !nameStart(s_[pos_])) fail("expected a name");
    std::size_t b = pos_;
    while (pos_ < s_.size() && nameChar(s_[pos_])) ++pos_;
    return s_.substr(b, pos_ - b);
  }

  // Decodes character data up to (not including) any of the stop characters; '<' and a bare '&' are errors inside
  // attribute values, as XML requires.
  std::string chars(char stop) {
    std::string out;
    while (pos_ < s_.size() && s_[pos_] != stop) {
      char c = s_[pos_];
      if (c == '<') {
        if (stop == '<') break;
        fail("'<' inside an attribute value");
      }
      if (c == '&') {
        std::size_t semi = s_.find(';', pos_);
        if (semi == std::string::npos || semi - pos_ > 12) fail("unterminated entity reference");
        std::string ent = s_.substr(pos_ + 1, semi - pos_ - 1);
        if (ent == "amp")
          out += '&';
        else if (ent == "lt")
          out += '<';
        else if (ent == "gt")
          out += '>';
        else if (ent == "quot")
          out += '"';
        else if (ent == "apos")
          out += '\'';
        else if (ent.size() > 1 && ent[0] == '#') {
          bool hex = ent[1] == 'x';
          std::string digits = ent.substr(hex ? 2 : 1);
          if (digits.empty()) fail("empty character reference");
          for (char d : digits)
            if (!(hex ? std::isxdigit(static_cast<unsigned char>(d)) : std::isdigit(static_cast<unsigned char>(d))))
              fail("bad character reference &" + ent + ";");
          unsigned long code = std::stoul(digits, nullptr, hex ? 16 : 10);
          if (code == 0 || code > 0x10FFFF) fail("character reference out of range");
          out += code < 0x80 ? static_cast<char>(code) : '?';
        } else {
          fail("unknown entity &" + ent + ";");
        }
        pos_ = semi + 1;
        continue;
      }
      out += c;
      ++pos_;
    }
    return out;
  }

  XmlElement element() {
    ++pos_;  // '<'
    XmlElement e;
    e.name = name();
    for (;;) {
      std::size_t before = pos_;
      skipSpace();
      if (pos_ >= s_.size()) fail("unterminated start tag <" + e.name + ">");
      if (startsWith("/>")) {
        pos_ += 2;
        return e;
      }
      if (s_[pos_] == '>') {
        ++pos_;
        break;
      }
      if (pos_ == before) fail("expected whitespace before an attribute in <" + e.name + ">");
      std::string key = name();
      skipSpace();
      if (pos_ >= s_.size() || s_[pos_] != '=') fail("attribute " + key + " without '='");
      ++pos_;
      skipSpace();
      if (pos_ >= s_.size() || (s_[pos_] != '"' && s_[pos_] != '\'')) fail("attribute " + key + " not quoted");
      char quote = s_[pos_++];
      std::string value = chars(quote);
      if (pos_ >= s_.size()) fail("unterminated attribute " + key);
      ++pos_;
      if (!e.attributes.emplace(key, value).second) fail("duplicate attribute " + key + " in <" + e.name + ">");
    }
    // Content.
    for (;;) {
      if (pos_ >= s_.size()) fail("element <" + e.name + "> is not closed");
      if (startsWith("</")) {
        pos_ += 2;
        std::string closing = name();
        if (closing != e.name) fail("</" + closing + "> closes <" + e.name + ">");
        skipSpace();
        if (pos_ >= s_.size() || s_[pos_] != '>') fail("unterminated end tag </" + closing + ">");
        ++pos_;
        return e;
      }
      if (startsWith("<!--")) {
        comment();
        continue;
      }
      if (startsWith("<!") || startsWith("<?")) fail("unsupported markup (DTD, CDATA or processing instruction)");
      if (s_[pos_] == '<') {
        e.children.push_back(element());
        continue;
      }
      e.text += chars('<');
    }
  }

  const std::string& s_;
  std::size_t pos_ = 0;
};

}  // namespace

std::vector<const XmlElement*> XmlElement::findAll(const std::string& elementName, const std::string& attribute,
                                                   const std::string& value) const {
  std::vector<const XmlElement*> out;
  std::function<void(const XmlElement&)> walk = [&](const XmlElement& e) {
    if (e.name == elementName) {
      auto it = attribute.empty() ? e.attributes.end() : e.attributes.find(attribute);
      if (attribute.empty() || (it != e.attributes.end() && it->second == value)) out.push_back(&e);
    }
    for (const XmlElement& c : e.children) walk(c);
  };
  walk(*this);
  return out;
}

XmlElement parseXml(const std::string& text) {
  return Parser(text).document();
}

}  // namespace vplab

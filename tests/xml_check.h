#pragma once
// A strict, small XML 1.0 reader for the documents vplab writes itself (SVG charts): elements, attributes in quotes,
// text with the five predefined entities and numeric character references, comments, one XML declaration.
// No DTDs, CDATA or processing instructions besides the declaration: anything else is an error. It exists so the
// tests can check that a chart is well-formed and count its parts without an XML library.

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplab {

struct XmlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;  ///< entity references already decoded
  std::vector<XmlElement> children;
  std::string text;  ///< concatenated character data directly inside this element

  /// Every descendant (this one included) with the given name and, when attribute is non-empty, that attribute
  /// equal to value.
  std::vector<const XmlElement*> findAll(const std::string& elementName, const std::string& attribute = {},
                                         const std::string& value = {}) const;
};

/// Parses a whole document; throws XmlError with the line number of the first problem (mismatched or unclosed tag,
/// duplicate attribute, bad entity, text outside the root, more than one root, ...).
XmlElement parseXml(const std::string& text);

}  // namespace vplab

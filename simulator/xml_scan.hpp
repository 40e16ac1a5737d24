// A minimal reader for the XML that SUMO's tools write (.net.xml, .rou.xml): it visits every
// start tag with its attributes, in document order. No DTDs, no namespaces, no text content;
// enough to index edges and connections and to read duarouter's routes.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace statebench::sim {

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  // values unescaped

  // Value of an attribute, or `fallback` when absent.
  std::string Attribute(const std::string& key, const std::string& fallback = "") const;
  bool Has(const std::string& key) const;
};

// Calls `visit` for every start (or empty-element) tag. Throws std::runtime_error on a
// malformed tag.
void ForEachXmlElement(const std::string& text,
                       const std::function<void(const XmlElement&)>& visit);

std::string ReadTextFile(const std::filesystem::path& path);

// Escapes &, <, >, " for attribute values.
std::string XmlEscape(const std::string& text);

}  // namespace statebench::sim

#include "simulator/xml_scan.hpp"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace statebench::sim {
namespace {

std::string Unescape(const std::string& s) {
  if (s.find('&') == std::string::npos) return s;
  static const std::pair<const char*, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    bool replaced = false;
    if (s[i] == '&') {
      for (const auto& [entity, ch] : kEntities) {
        if (s.compare(i, std::char_traits<char>::length(entity), entity) == 0) {
          out.push_back(ch);
          i += std::char_traits<char>::length(entity);
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out.push_back(s[i++]);
  }
  return out;
}

bool IsNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == ':' ||
         c == '.';
}

}  // namespace

std::string XmlElement::Attribute(const std::string& key, const std::string& fallback) const {
  for (const auto& [k, v] : attributes) {
    if (k == key) return v;
  }
  return fallback;
}

bool XmlElement::Has(const std::string& key) const {
  for (const auto& kv : attributes) {
    if (kv.first == key) return true;
  }
  return false;
}

void ForEachXmlElement(const std::string& text,
                       const std::function<void(const XmlElement&)>& visit) {
  std::size_t i = 0;
  const std::size_t n = text.size();
  while ((i = text.find('<', i)) != std::string::npos) {
    if (text.compare(i, 4, "<!--") == 0) {
      const std::size_t end = text.find("-->", i);
      if (end == std::string::npos) throw std::runtime_error("unterminated XML comment");
      i = end + 3;
      continue;
    }
    if (i + 1 < n && (text[i + 1] == '?' || text[i + 1] == '/' || text[i + 1] == '!')) {
      i = text.find('>', i);
      if (i == std::string::npos) break;
      continue;
    }
    XmlElement element;
    std::size_t j = i + 1;
    while (j < n && IsNameChar(text[j])) element.name.push_back(text[j++]);
    for (;;) {
      while (j < n && std::isspace(static_cast<unsigned char>(text[j])) != 0) ++j;
      if (j >= n) throw std::runtime_error("unterminated XML tag <" + element.name);
      if (text[j] == '>' || text[j] == '/') break;
      std::string key;
      while (j < n && IsNameChar(text[j])) key.push_back(text[j++]);
      if (key.empty() || j + 1 >= n || text[j] != '=' ||
          (text[j + 1] != '"' && text[j + 1] != '\'')) {
        throw std::runtime_error("malformed attribute in XML tag <" + element.name);
      }
      const char quote = text[j + 1];
      const std::size_t end = text.find(quote, j + 2);
      if (end == std::string::npos) throw std::runtime_error("unterminated XML attribute");
      element.attributes.emplace_back(key, Unescape(text.substr(j + 2, end - j - 2)));
      j = end + 1;
    }
    visit(element);
    i = text.find('>', j);
    if (i == std::string::npos) break;
  }
}

std::string ReadTextFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out.push_back(c);
    }
  }
  return out;
}

}  // namespace statebench::sim

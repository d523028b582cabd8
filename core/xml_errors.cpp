// Explaining why an experiment file is not a usable XML document (see
// core/xml_errors.h).
#include "core/xml_errors.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace colony {

namespace {

[[noreturn]] void Fail(const std::string& file, int line, const std::string& message) {
  throw ConfigError(std::vector<Diagnostic>{Diagnostic{file, line, "", "", "", message}});
}

// The elements still open where `text` ends, outermost first (a best-effort
// scan, used only to explain why a document failed to parse).
struct OpenElement {
  std::string name;
  int line = 0;
};
std::vector<OpenElement> OpenElementsAtEnd(const std::string& text) {
  std::vector<OpenElement> open;
  int line = 1;
  size_t i = 0;
  auto skip_past = [&](const char* terminator) {
    const size_t k = text.find(terminator, i);
    const size_t stop = k == std::string::npos ? text.size() : k + std::strlen(terminator);
    line += static_cast<int>(std::count(text.begin() + i, text.begin() + stop, '\n'));
    i = stop;
  };
  while (i < text.size()) {
    if (text[i] != '<') {
      if (text[i] == '\n') ++line;
      ++i;
      continue;
    }
    if (text.compare(i, 4, "<!--") == 0) {
      skip_past("-->");
    } else if (text.compare(i, 9, "<![CDATA[") == 0) {
      skip_past("]]>");
    } else if (text.compare(i, 2, "<?") == 0) {
      skip_past("?>");
    } else if (text.compare(i, 2, "<!") == 0) {
      skip_past(">");
    } else {
      const int tag_line = line;
      const bool closing = text.compare(i, 2, "</") == 0;
      size_t k = i + (closing ? 2 : 1);
      const size_t name_begin = k;
      while (k < text.size() && !std::isspace(static_cast<unsigned char>(text[k])) &&
             text[k] != '>' && text[k] != '/') {
        ++k;
      }
      const std::string name = text.substr(name_begin, k - name_begin);
      char quote = 0;
      for (; k < text.size() && (quote || text[k] != '>'); ++k) {
        if (text[k] == '\n') ++line;
        if (quote) {
          if (text[k] == quote) quote = 0;
        } else if (text[k] == '"' || text[k] == '\'') {
          quote = text[k];
        }
      }
      const bool self_closing = k < text.size() && text[k - 1] == '/';
      if (closing) {
        if (!open.empty()) open.pop_back();
      } else if (!self_closing) {
        open.push_back({name, tag_line});
      }
      i = k + 1;
    }
  }
  return open;
}

// Explains a failed parse of `text` as one diagnostic.
[[noreturn]] void FailXml(const tinyxml2::XMLDocument& doc, tinyxml2::XMLError err,
                          const std::string& text, const std::string& file) {
  // tinyxml2 names the element it was reading as "... name=NAME".
  const std::string detail = doc.ErrorStr() ? doc.ErrorStr() : "";
  const size_t at = detail.find("name=");
  const std::string element = at == std::string::npos ? "" : detail.substr(at + 5);
  const auto open = OpenElementsAtEnd(text);
  std::string truncated;
  int line = doc.ErrorLineNum();
  if (!open.empty()) {
    const OpenElement& last = open.back();
    truncated = "the file ends inside <" + last.name + "> (line " + std::to_string(last.line) +
                "), which is never closed with </" + last.name + ">; is the file truncated?";
  }
  std::string message;
  switch (err) {
    case tinyxml2::XML_ERROR_PARSING_TEXT:
      if (text.find('<') == std::string::npos) {
        Fail(file, 1,
             "this is not XML: an experiment file is an XML document with root element <colony>");
      } else {
        // With every element closed, the text stands outside the root element.
        message = truncated.empty()
                      ? "text outside the root element; accepted: one root element, with only "
                        "comments and the <?xml ...?> declaration around it"
                      : truncated;
      }
      break;
    case tinyxml2::XML_ERROR_PARSING:
      if (!truncated.empty()) line = open.back().line;
      message =
          truncated.empty() ? "the document ends unexpectedly; is the file truncated?" : truncated;
      break;
    case tinyxml2::XML_ERROR_PARSING_ELEMENT:
      message =
          (element.empty() ? "a tag" : "the tag <" + element + ">") +
          " is malformed or unfinished; accepted: <name attribute=\"value\" ...> or <name .../>";
      break;
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      message = "<" + element + "> is not closed by a matching </" + element + ">";
      break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      message = "malformed or repeated attribute" +
                (element.empty() ? "" : " in <" + element + ">") +
                "; accepted: name=\"value\" with the value in quotes, each attribute once";
      break;
    case tinyxml2::XML_ERROR_PARSING_COMMENT:
      message = "a comment is not closed: it starts with <!-- and must end with -->";
      break;
    case tinyxml2::XML_ERROR_PARSING_CDATA:
      message = "a <![CDATA[ section is not closed with ]]>";
      break;
    case tinyxml2::XML_ERROR_PARSING_DECLARATION:
      message =
          "malformed declaration; accepted: <?xml version=\"1.0\"?> at the very start of the file";
      break;
    default:
      message = std::string(doc.ErrorName()) + (detail.empty() ? "" : ": " + detail);
  }
  if (err != tinyxml2::XML_ERROR_PARSING && !truncated.empty() &&
      message.find(truncated) == std::string::npos) {
    message += "; " + truncated;
  }
  Fail(file, line, "not well-formed XML: " + message);
}

}  // namespace

std::string ReadExperimentText(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    Fail(file, 0, "cannot open the experiment file: no such file");
  if (std::filesystem::is_directory(file, ec))
    Fail(file, 0, "cannot open the experiment file: it is a directory");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  if (!in) Fail(file, 0, "cannot read the experiment file");
  return content.str();
}

void ParseExperimentXml(const std::string& text, const std::string& file,
                        tinyxml2::XMLDocument& doc) {
  const tinyxml2::XMLError err = doc.Parse(text.c_str(), text.size());
  if (err == tinyxml2::XML_ERROR_EMPTY_DOCUMENT)
    Fail(file, 0, "the file is empty; expected an XML document with root <colony>");
  if (err == tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED) {
    Fail(file, doc.ErrorLineNum(),
         "elements nested too deeply (over " + std::to_string(TINYXML2_MAX_ELEMENT_DEPTH) +
             " levels)");
  }
  if (err != tinyxml2::XML_SUCCESS) FailXml(doc, err, text, file);
  if (!doc.RootElement()) Fail(file, 0, "no root element; expected <colony>");
  const std::string root = doc.RootElement()->Name();
  if (root != "colony" && root != "argos-configuration") {
    Fail(file, doc.RootElement()->GetLineNum(),
         "the root element is <" + root + ">; accepted: <colony> or <argos-configuration>");
  }
  // tinyxml2 keeps whatever follows the root element; only comments may.
  for (const tinyxml2::XMLNode* n = doc.RootElement()->NextSibling(); n; n = n->NextSibling()) {
    const std::string what = n->ToElement()
                                 ? "a second root element <" + std::string(n->Value()) + ">"
                             : n->ToText() ? "text"
                                           : "";
    if (what.empty()) continue;
    Fail(file, n->GetLineNum(),
         what + " after </" + root + "> (which closes the root element opened at line " +
             std::to_string(doc.RootElement()->GetLineNum()) +
             "); accepted: one root element, followed only by comments");
  }
}

}  // namespace colony

// Reading an experiment file into an XML document, every way it can fail
// explained in one diagnostic (file, line, what is wrong, what is accepted):
// a missing or unreadable file, text that is not XML, malformed or truncated
// XML, a root element other than <colony>, content after the root element.
// Raw parser codes (XML_ERROR_...) never reach the user.
#pragma once

#include <string>

namespace tinyxml2 {
class XMLDocument;
}

namespace colony {

// The whole text of the experiment file `file`. Throws ConfigError if it is
// missing, a directory or unreadable.
std::string ReadExperimentText(const std::string& file);

// Parses `text` into `doc` and checks that it holds one root element, <colony>
// or <argos-configuration>, followed only by comments. Throws ConfigError
// naming `file` and the line.
void ParseExperimentXml(const std::string& text, const std::string& file,
                        tinyxml2::XMLDocument& doc);

}  // namespace colony

// ARGoS experiment files (root <argos-configuration>) read as they are: the
// loader rewrites, in the parsed document and before reading it, what ARGoS
// writes differently from Colony, and says once what it ignored. Colony's own
// <colony> files are never touched. docs/coming-from-argos.md lists every
// rule.
#pragma once

#include <string>

namespace tinyxml2 {
class XMLDocument;
}

namespace colony {

// Rewrites `doc` in place when its root is <argos-configuration>; logs one
// notice naming what a headless run ignores (GUI sections, show_rays...).
void AdaptArgosDocument(tinyxml2::XMLDocument& doc, const std::string& file);

}  // namespace colony

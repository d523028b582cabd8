// Command-line overrides of an experiment file (`colony run --set PATH=VALUE`),
// applied to the parsed document before it is read, so that an overridden
// value is checked exactly as if the file said it and the resolved experiment
// (experiment.xml of a run) shows it.
#pragma once

#include <string>

namespace tinyxml2 {
class XMLDocument;
}

namespace colony {

// Applies one "a.b[id].c=value" to `doc`. Path segments are element names
// below the root (the root's own name may lead), optionally with [id] to pick
// among siblings; the last segment is the attribute, set or added. Throws
// ConfigError naming the override, and the element of `file` where the path
// leads nowhere.
void ApplyOverride(tinyxml2::XMLDocument& doc, const std::string& spec, const std::string& file);

}  // namespace colony

// Command-line overrides (see core/overrides.h).
#include "core/overrides.h"

#include <tinyxml2.h>

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "core/text.h"

namespace colony {

void ApplyOverride(tinyxml2::XMLDocument& doc, const std::string& spec, const std::string& file) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ConfigError("--set '" + spec +
                      "': expected PATH=VALUE, e.g. framework.experiment.length=10");
  }
  const std::string path = spec.substr(0, eq);
  const std::string value = spec.substr(eq + 1);
  auto segments = SplitList(path, '.');
  tinyxml2::XMLElement* element = doc.RootElement();
  if (!segments.empty() && segments.front() == element->Name()) segments.erase(segments.begin());
  if (segments.size() < 2) {
    throw ConfigError("--set '" + spec +
                      "': the path needs at least an element and an attribute, e.g. "
                      "framework.experiment.length=10");
  }
  for (const auto& segment : segments) {
    if (segment.empty()) {
      throw ConfigError("--set '" + spec +
                        "': empty name in the path; accepted: element.element[id].attribute=value, "
                        "e.g. framework.experiment.length=10");
    }
  }
  for (size_t i = 0; i + 1 < segments.size(); ++i) {
    std::string name = segments[i], id;
    const size_t bracket = name.find('[');
    if (bracket != std::string::npos) {
      if (name.back() != ']')
        throw ConfigError("--set '" + spec + "': malformed segment '" + name +
                          "'; accepted: name or name[id]");
      id = name.substr(bracket + 1, name.size() - bracket - 2);
      name = name.substr(0, bracket);
    }
    std::vector<tinyxml2::XMLElement*> matches;
    std::vector<std::string> names;
    for (auto* c = element->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::find(names.begin(), names.end(), c->Name()) == names.end())
        names.push_back(c->Name());
      if (name != c->Name()) continue;
      if (!id.empty() && (!c->Attribute("id") || id != c->Attribute("id"))) continue;
      matches.push_back(c);
    }
    if (matches.empty()) {
      std::string message =
          "--set '" + spec + "': no element <" + segments[i] + "> inside <" + element->Name() + ">";
      const std::string guess = DidYouMean(name, names);
      if (!guess.empty() && guess != name) message += " (did you mean '" + guess + "'?)";
      message +=
          names.empty() ? std::string("; it has no child elements") : "; it holds: " + Join(names);
      throw ConfigError(
          std::vector<Diagnostic>{Diagnostic{file, element->GetLineNum(), "", "", path, message}});
    }
    if (matches.size() > 1) {
      throw ConfigError("--set '" + spec + "': <" + name + "> matches " +
                        std::to_string(matches.size()) + " elements inside <" + element->Name() +
                        ">; pick one with " + name + "[id]");
    }
    element = matches.front();
  }
  element->SetAttribute(segments.back().c_str(), value.c_str());
}

}  // namespace colony

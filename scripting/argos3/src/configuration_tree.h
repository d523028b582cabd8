// ARGoS compatibility layer (Colony), internal: the configuration tree built
// from a controller's or loop functions' parameters.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "argos3/core/utility/configuration/argos_configuration.h"
#include "core/control_interface.h"

namespace argos {

struct TConfigurationNode::Data {
  struct Attribute {
    std::string name;
    std::string value;
    bool read = false;
  };
  std::string name;
  std::string path;  // dotted path from the root: "" for the root, "wheel_turning"...
  std::vector<Attribute> attributes;
  std::vector<TConfigurationNode> children;
};

namespace internal {

using ParameterList = std::vector<std::pair<std::string, std::string>>;

// The tree named `root`: each parameter an attribute, a dotted name
// ("a.b.c") the attribute c of the child b of the child a. A name ending with
// a dot ("a.") makes the child a with no attribute.
TConfigurationNode BuildConfigurationTree(const std::string& root, const ParameterList& parameters);

// Every attribute of the tree never read, as its dotted name.
std::vector<std::string> UnreadAttributes(const TConfigurationNode& root);

// Every parameter of `params` with its value, in the file's order; they all
// count as read for Colony (the tree reports the unread ones instead).
// `first_reader` is set when no one had read them before: the first robot of
// a controller configuration (which then reports what its controller left
// unread, once for all robots).
ParameterList TakeParameters(const colony::Params& params, bool& first_reader);

// Colony's error for a configuration error of an ARGoS controller or loop
// functions (`error.parameter()` not empty) reading `tree`: it names the
// parameter, and the parameters given but not read (a misspelt name).
colony::ParamError ToParamError(const CARGoSException& error, const TConfigurationNode& tree);

}  // namespace internal
}  // namespace argos

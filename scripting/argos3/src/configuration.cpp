#include <cxxabi.h>

#include <algorithm>
#include <cstdlib>
#include <memory>

#include "configuration_tree.h"

namespace argos {

TConfigurationNode::TConfigurationNode() : data_(std::make_shared<Data>()) {}

const std::string& TConfigurationNode::Value() const { return data_->name; }

TConfigurationNodeIterator TConfigurationNodeIterator::begin(TConfigurationNode* parent) const {
  TConfigurationNodeIterator it(tag_);
  it.parent_ = parent;
  it.Seek(0);
  return it;
}

TConfigurationNodeIterator& TConfigurationNodeIterator::operator++() {
  Seek(index_ + 1);
  return *this;
}

void TConfigurationNodeIterator::Seek(size_t from) {
  node_ = nullptr;
  if (parent_ == nullptr) return;
  auto& children = parent_->data().children;
  for (index_ = from; index_ < children.size(); ++index_) {
    if (tag_.empty() || children[index_].Value() == tag_) {
      node_ = &children[index_];
      return;
    }
  }
}

namespace {

std::string Dotted(const std::string& path, const std::string& name) {
  return path.empty() ? name : path + "." + name;
}

TConfigurationNode* FindChild(TConfigurationNode& node, const std::string& tag) {
  for (auto& child : node.data().children)
    if (child.Value() == tag) return &child;
  return nullptr;
}

TConfigurationNode& ChildFor(TConfigurationNode& node, const std::string& tag) {
  if (TConfigurationNode* child = FindChild(node, tag)) return *child;
  auto data = std::make_shared<TConfigurationNode::Data>();
  data->name = tag;
  data->path = Dotted(node.data().path, tag);
  node.data().children.emplace_back(std::move(data));
  return node.data().children.back();
}

void CollectUnread(const TConfigurationNode& node, std::vector<std::string>& out) {
  for (const auto& a : node.data().attributes)
    if (!a.read) out.push_back(Dotted(node.data().path, a.name));
  for (const auto& child : node.data().children) CollectUnread(child, out);
}

}  // namespace

bool NodeExists(TConfigurationNode& node, const std::string& tag) noexcept {
  return FindChild(node, tag) != nullptr;
}

TConfigurationNode& GetNode(TConfigurationNode& node, const std::string& tag) {
  if (TConfigurationNode* child = FindChild(node, tag)) return *child;
  CARGoSException error("Node '" + tag + "' not found in <" + node.Value() + ">");
  error.SetParameter(Dotted(node.data().path, tag), "");
  throw error;
}

bool NodeAttributeExists(TConfigurationNode& node, const std::string& name) {
  return internal::FindAttribute(node, name) != nullptr;
}

namespace internal {

const std::string* FindAttribute(TConfigurationNode& node, const std::string& name) {
  for (auto& a : node.data().attributes) {
    if (a.name != name) continue;
    a.read = true;
    return &a.value;
  }
  return nullptr;
}

void ThrowMissingAttribute(TConfigurationNode& node, const std::string& name) {
  CARGoSException error("Error parsing attribute \"" + name + "\": <" + node.Value() +
                        "> has no attribute \"" + name + "\"");
  error.SetParameter(Dotted(node.data().path, name), "");
  throw error;
}

void ThrowMalformedAttribute(TConfigurationNode& node, const std::string& name,
                             const std::string& text, const std::string& accepted) {
  CARGoSException error("Error parsing attribute \"" + name + "\" of <" + node.Value() + ">: '" +
                        text + "' is not accepted; accepted: " + accepted);
  error.SetParameter(Dotted(node.data().path, name), text);
  throw error;
}

std::string TypeName(const std::type_info& type) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> name(
      abi::__cxa_demangle(type.name(), nullptr, nullptr, &status), std::free);
  return status == 0 && name ? std::string(name.get()) : std::string(type.name());
}

TConfigurationNode BuildConfigurationTree(const std::string& root,
                                          const ParameterList& parameters) {
  TConfigurationNode tree;
  tree.data().name = root;
  for (const auto& [key, value] : parameters) {
    TConfigurationNode* node = &tree;
    size_t begin = 0;
    for (size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', begin)) {
      node = &ChildFor(*node, key.substr(begin, dot - begin));
      begin = dot + 1;
    }
    if (begin < key.size()) node->data().attributes.push_back({key.substr(begin), value, false});
  }
  return tree;
}

std::vector<std::string> UnreadAttributes(const TConfigurationNode& root) {
  std::vector<std::string> out;
  CollectUnread(root, out);
  return out;
}

ParameterList TakeParameters(const colony::Params& params, bool& first_reader) {
  std::vector<std::string> keys = params.Unread();
  first_reader = !keys.empty();
  // Parameters read before (by an earlier robot of this configuration).
  for (const auto& key : params.Asked()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end() && params.Has(key))
      keys.push_back(key);
  }
  ParameterList out;
  out.reserve(keys.size());
  for (const auto& key : keys) out.emplace_back(key, params.GetString(key));
  return out;
}

colony::ParamError ToParamError(const CARGoSException& error, const TConfigurationNode& tree) {
  std::string message = error.what();
  const std::vector<std::string> unread = UnreadAttributes(tree);
  if (error.value().empty() && !unread.empty()) {
    message += "\n(given but not read: ";
    for (size_t i = 0; i < unread.size(); ++i) message += (i ? ", " : "") + unread[i];
    message += ")";
  }
  return colony::ParamError(error.parameter(), error.value(), message);
}

}  // namespace internal
}  // namespace argos

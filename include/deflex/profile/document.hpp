// A YAML document kept whole for the modules that read their own sections of
// it (stiffness reads the holder: and stiffness: sections of a machine
// profile). Opaque, so that yaml-cpp stays out of the public headers: the
// modules that parse YAML reach its node through deflex/profile/yaml.hpp, a
// header of this build that is not installed (src/profile/internal/).
#pragma once
#include <memory>
#include <utility>

namespace deflex::yaml {

class Document {
 public:
  struct Node;  // holds the YAML::Node (deflex/profile/yaml.hpp)
  Document() = default;
  explicit Document(std::shared_ptr<const Node> node) : node_(std::move(node)) {}
  // Whether a document was read (the built-in defaults have none).
  explicit operator bool() const { return node_ != nullptr; }
  const Node* node() const { return node_.get(); }

 private:
  std::shared_ptr<const Node> node_;
};

}  // namespace deflex::yaml

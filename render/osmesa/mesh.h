// Meshes loaded through assimp (OBJ, glTF, STL, COLLADA and the other
// formats it reads), drawn instead of an entity's simple shape.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/color.h"
#include "core/math.h"
#include "core/space.h"

namespace colony::render {

// Triangles in the frame of the entity they dress (origin at the centre of
// its base, x forwards, z up): three entries per triangle in each array.
struct Mesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<Color> colors;
};

// How a mesh file sits in its entity's frame.
struct MeshPlacement {
  double scale = 1;            // applied first, about the file's origin
  Pose offset;                 // then this rotation and translation
  std::optional<Color> color;  // replaces the file's colours when given
};

// Loads `path`. Returns an error message, or "" on success.
std::string LoadMesh(const std::string& path, const MeshPlacement& placement, Mesh& mesh);

// Which entities are drawn with which mesh: by entity id, else by type.
class MeshTable {
 public:
  void BindType(const std::string& type, std::shared_ptr<const Mesh> mesh) {
    by_type_[type] = std::move(mesh);
  }
  void BindEntity(const std::string& id, std::shared_ptr<const Mesh> mesh) {
    by_id_[id] = std::move(mesh);
  }
  // The mesh of the entity in `slot`, or nullptr.
  const Mesh* For(const Space& space, uint32_t slot) const {
    if (!by_id_.empty()) {
      if (auto it = by_id_.find(space.id(slot)); it != by_id_.end()) return it->second.get();
    }
    if (!by_type_.empty()) {
      if (auto it = by_type_.find(space.TypeLabel(space.type(slot))); it != by_type_.end()) {
        return it->second.get();
      }
    }
    return nullptr;
  }

 private:
  std::unordered_map<std::string, std::shared_ptr<const Mesh>> by_type_, by_id_;
};

}  // namespace colony::render

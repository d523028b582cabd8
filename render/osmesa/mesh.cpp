#include "render/osmesa/mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>

namespace colony::render {
namespace {

Color ToColor(const aiColor4D& c) {
  auto channel = [](float v) {
    return static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
  };
  return {channel(c.r), channel(c.g), channel(c.b), 255};
}

Color MaterialColor(const aiScene& scene, const aiMesh& mesh) {
  aiColor4D diffuse(0.7f, 0.7f, 0.7f, 1.0f);
  if (mesh.mMaterialIndex < scene.mNumMaterials) {
    aiGetMaterialColor(scene.mMaterials[mesh.mMaterialIndex], AI_MATKEY_COLOR_DIFFUSE, &diffuse);
  }
  return ToColor(diffuse);
}

void AppendTriangles(const aiScene& scene, const aiMesh& m, const MeshPlacement& placement,
                     Mesh& out) {
  const Eigen::Matrix3d rotation = placement.offset.orientation.toRotationMatrix();
  const Color material = placement.color.value_or(MaterialColor(scene, m));
  const bool vertex_colors = !placement.color && m.HasVertexColors(0);
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines
    for (unsigned k = 0; k < 3; ++k) {
      const unsigned i = face.mIndices[k];
      const aiVector3D& v = m.mVertices[i];
      const Vec3 p = placement.offset.position + rotation * (placement.scale * Vec3(v.x, v.y, v.z));
      const aiVector3D n = m.HasNormals() ? m.mNormals[i] : aiVector3D(0, 0, 1);
      out.positions.push_back(p.cast<float>());
      out.normals.push_back((rotation * Vec3(n.x, n.y, n.z)).normalized().cast<float>());
      out.colors.push_back(vertex_colors ? ToColor(m.mColors[0][i]) : material);
    }
  }
}

}  // namespace

std::string LoadMesh(const std::string& path, const MeshPlacement& placement, Mesh& mesh) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_GenSmoothNormals | aiProcess_PreTransformVertices);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
    return "cannot read mesh file '" + path + "': " + importer.GetErrorString();
  }
  mesh = Mesh{};
  for (unsigned i = 0; i < scene->mNumMeshes; ++i)
    AppendTriangles(*scene, *scene->mMeshes[i], placement, mesh);
  if (mesh.positions.empty()) return "mesh file '" + path + "' holds no triangles";
  return "";
}

}  // namespace colony::render

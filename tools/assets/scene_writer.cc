#include "hadal/assets/scene_writer.h"
#include "hadal/core/units.h"

#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/texture.h>

#include <algorithm>
#include <assimp/Exporter.hpp>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace hadal::assets {
namespace {

std::string lower_extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string directory_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

aiMesh* to_ai_mesh(const MeshData& d, unsigned material) {
  auto* m = new aiMesh();
  m->mName = aiString(d.name);
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mMaterialIndex = material;
  const auto nv = static_cast<unsigned>(d.num_vertices());
  m->mNumVertices = nv;
  m->mVertices = new aiVector3D[nv];
  for (unsigned v = 0; v < nv; ++v)
    m->mVertices[v] =
        aiVector3D(d.positions[3 * v], d.positions[3 * v + 1], d.positions[3 * v + 2]);
  if (!d.normals.empty()) {
    m->mNormals = new aiVector3D[nv];
    for (unsigned v = 0; v < nv; ++v)
      m->mNormals[v] = aiVector3D(d.normals[3 * v], d.normals[3 * v + 1], d.normals[3 * v + 2]);
  }
  if (!d.uvs.empty()) {
    m->mTextureCoords[0] = new aiVector3D[nv];
    m->mNumUVComponents[0] = 2;
    for (unsigned v = 0; v < nv; ++v)
      m->mTextureCoords[0][v] = aiVector3D(d.uvs[2 * v], d.uvs[2 * v + 1], 0.0f);
  }
  const auto nf = static_cast<unsigned>(d.num_triangles());
  m->mNumFaces = nf;
  m->mFaces = new aiFace[nf];
  for (unsigned f = 0; f < nf; ++f) {
    m->mFaces[f].mNumIndices = 3;
    m->mFaces[f].mIndices =
        new unsigned[3]{d.indices[3 * f], d.indices[3 * f + 1], d.indices[3 * f + 2]};
  }
  return m;
}

aiNode* to_ai_node(const SceneNode& n) {
  auto* node = new aiNode(n.name);
  const auto& t = n.transform;
  node->mTransformation =
      aiMatrix4x4(float(t[0]), float(t[1]), float(t[2]), float(t[3]), float(t[4]), float(t[5]),
                  float(t[6]), float(t[7]), float(t[8]), float(t[9]), float(t[10]), float(t[11]),
                  float(t[12]), float(t[13]), float(t[14]), float(t[15]));
  if (!n.meshes.empty()) {
    node->mNumMeshes = static_cast<unsigned>(n.meshes.size());
    node->mMeshes = new unsigned[n.meshes.size()];
    std::copy(n.meshes.begin(), n.meshes.end(), node->mMeshes);
  }
  if (!n.children.empty()) {
    node->mNumChildren = static_cast<unsigned>(n.children.size());
    node->mChildren = new aiNode*[n.children.size()];
    for (std::size_t c = 0; c < n.children.size(); ++c) {
      node->mChildren[c] = to_ai_node(n.children[c]);
      node->mChildren[c]->mParent = node;
    }
  }
  return node;
}

}  // namespace

SceneSpec single_mesh_scene(MeshData mesh, SceneMaterial material) {
  SceneSpec spec;
  spec.root.name = mesh.name.empty() ? "root" : mesh.name;
  spec.meshes.push_back(std::move(mesh));
  spec.mesh_materials = {0};
  spec.materials = {std::move(material)};
  spec.root.meshes = {0};
  return spec;
}

std::array<double, 16> rigid_transform(const double axis[3], double angle, const double t[3]) {
  const double c = std::cos(angle), s = std::sin(angle), C = 1.0 - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  return {x * x * C + c,
          x * y * C - z * s,
          x * z * C + y * s,
          t[0],
          y * x * C + z * s,
          y * y * C + c,
          y * z * C - x * s,
          t[1],
          z * x * C - y * s,
          z * y * C + x * s,
          z * z * C + c,
          t[2],
          0.0,
          0.0,
          0.0,
          1.0};
}

SceneSpec two_node_scene() {
  SceneSpec spec;
  spec.meshes.push_back(make_box(1.0, 1.0, 1.0));
  spec.meshes[0].name = "root_cube";
  spec.meshes.push_back(make_box(2.0, 1.0, 1.0));
  spec.meshes[1].name = "child_box";
  spec.mesh_materials = {0, 0};
  spec.materials = {SceneMaterial{}};
  const double z_axis[3] = {0, 0, 1}, root_t[3] = {0, 0, 5}, child_t[3] = {10, 0, 0};
  spec.root.name = "root";
  spec.root.transform = rigid_transform(z_axis, 0.0, root_t);
  spec.root.meshes = {0};
  SceneNode child;
  child.name = "child";
  child.transform = rigid_transform(z_axis, 0.5 * kPi, child_t);
  child.meshes = {1};
  spec.root.children.push_back(child);
  return spec;
}

std::array<std::uint8_t, 3> test_texture_pixel(int x, int y) {
  return {static_cast<std::uint8_t>((x * 37 + 11) & 255),
          static_cast<std::uint8_t>((y * 53 + 7) & 255),
          static_cast<std::uint8_t>(((x ^ y) * 17) & 255)};
}

std::vector<std::uint8_t> make_test_texture_png(int width, int height) {
  cv::Mat bgr(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const auto rgb = test_texture_pixel(x, y);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
    }
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", bgr, png))
    throw std::runtime_error("make_test_texture_png: PNG encoding failed");
  return png;
}

SceneSpec textured_quad_scene(int texture_width, int texture_height,
                              const std::string& external_file) {
  MeshData quad;
  quad.name = "quad";
  quad.positions = {-0.5f, -0.5f, 0.0f, 0.5f, -0.5f, 0.0f, 0.5f, 0.5f, 0.0f, -0.5f, 0.5f, 0.0f};
  quad.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  quad.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  quad.indices = {0, 1, 2, 0, 2, 3};
  SceneMaterial material;
  material.name = "textured";
  material.base_color = {1.0f, 0.5f, 0.25f, 1.0f};
  material.texture_png = make_test_texture_png(texture_width, texture_height);
  material.texture_file = external_file;
  return single_mesh_scene(std::move(quad), std::move(material));
}

std::unique_ptr<aiScene> build_ai_scene(const SceneSpec& spec) {
  auto scene = std::make_unique<aiScene>();
  std::vector<SceneMaterial> materials = spec.materials;
  if (materials.empty()) materials.emplace_back();

  // Embedded textures first, so materials can refer to them as "*N".
  std::vector<const SceneMaterial*> embedded;
  for (const auto& m : materials)
    if (!m.texture_png.empty() && m.texture_file.empty()) embedded.push_back(&m);
  if (!embedded.empty()) {
    scene->mNumTextures = static_cast<unsigned>(embedded.size());
    scene->mTextures = new aiTexture*[embedded.size()];
    for (std::size_t i = 0; i < embedded.size(); ++i) {
      auto* tex = new aiTexture();
      const auto& png = embedded[i]->texture_png;
      tex->mWidth = static_cast<unsigned>(png.size());  // compressed: mWidth = byte count
      tex->mHeight = 0;
      std::strcpy(tex->achFormatHint, "png");
      tex->pcData = new aiTexel[(png.size() + sizeof(aiTexel) - 1) / sizeof(aiTexel)];
      std::memcpy(tex->pcData, png.data(), png.size());
      tex->mFilename = aiString(embedded[i]->name + ".png");
      scene->mTextures[i] = tex;
    }
  }

  scene->mNumMaterials = static_cast<unsigned>(materials.size());
  scene->mMaterials = new aiMaterial*[materials.size()];
  unsigned next_embedded = 0;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    auto* mat = new aiMaterial();
    const SceneMaterial& m = materials[i];
    const aiString name(m.name);
    mat->AddProperty(&name, AI_MATKEY_NAME);
    const aiColor4D color(m.base_color[0], m.base_color[1], m.base_color[2], m.base_color[3]);
    mat->AddProperty(&color, 1, AI_MATKEY_BASE_COLOR);
    mat->AddProperty(&color, 1, AI_MATKEY_COLOR_DIFFUSE);
    if (!m.texture_png.empty()) {
      const aiString path(m.texture_file.empty() ? "*" + std::to_string(next_embedded++)
                                                 : m.texture_file);
      mat->AddProperty(&path, AI_MATKEY_TEXTURE(aiTextureType_BASE_COLOR, 0));
      mat->AddProperty(&path, AI_MATKEY_TEXTURE(aiTextureType_DIFFUSE, 0));
    }
    scene->mMaterials[i] = mat;
  }

  scene->mNumMeshes = static_cast<unsigned>(spec.meshes.size());
  scene->mMeshes = new aiMesh*[spec.meshes.size()];
  for (std::size_t i = 0; i < spec.meshes.size(); ++i) {
    const unsigned material = i < spec.mesh_materials.size() ? spec.mesh_materials[i] : 0;
    if (material >= materials.size())
      throw std::invalid_argument("build_ai_scene: material index out of range");
    scene->mMeshes[i] = to_ai_mesh(spec.meshes[i], material);
  }

  SceneNode root = spec.root;
  if (root.meshes.empty() && root.children.empty())
    for (unsigned i = 0; i < spec.meshes.size(); ++i) root.meshes.push_back(i);
  scene->mRootNode = to_ai_node(root);
  return scene;
}

std::string write_scene(const SceneSpec& spec, const std::string& path, bool stl_ascii) {
  const std::string ext = lower_extension(path);
  const char* format = nullptr;
  if (ext == ".glb")
    format = "glb2";
  else if (ext == ".gltf")
    format = "gltf2";
  else if (ext == ".obj")
    format = "obj";
  else if (ext == ".stl")
    format = stl_ascii ? "stl" : "stlb";
  else
    return path + ": unsupported extension '" + ext + "' (supported: .glb, .gltf, .obj, .stl)";

  for (const auto& m : spec.materials) {
    if (m.texture_png.empty() || m.texture_file.empty()) continue;
    const std::string texture_path = directory_of(path) + "/" + m.texture_file;
    std::ofstream out(texture_path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(m.texture_png.data()),
              static_cast<std::streamsize>(m.texture_png.size()));
    if (!out) return texture_path + ": cannot write texture";
  }
  std::unique_ptr<aiScene> scene;
  try {
    scene = build_ai_scene(spec);
  } catch (const std::exception& e) {
    return path + ": " + e.what();
  }
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), format, path) != aiReturn_SUCCESS)
    return path + ": export failed: " + exporter.GetErrorString();
  return "";
}

}  // namespace hadal::assets

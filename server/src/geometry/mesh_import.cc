#include "hadal/geometry/mesh_import.h"
#include "hadal/core/parallel_for.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <assimp/IOStream.hpp>
#include <assimp/Importer.hpp>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <thread>

namespace hadal::geometry {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kGlbChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kGlbChunkBin = 0x004E4942;   // "BIN\0"
constexpr std::uint32_t kDropped = 0xFFFFFFFFu;      // index marking a dropped triangle
constexpr std::size_t kChunk = 1 << 16;              // vertices or faces per work item
constexpr int kMaxNodeDepth = 1024;
constexpr std::size_t kBackgroundCleanupFaces = 1 << 16;  // ~1 ms of freeing

unsigned worker_threads() {
  static const unsigned n = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  return n;
}

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
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::uint32_t read_u32_le(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

// Checks a GLB container (glTF 2.0 binary: 12-byte header, then 8-byte-headed chunks, JSON first)
// against the file's real size, so truncated or corrupt containers never reach assimp's reader.
// Returns the problem, or "" when the container is consistent.
std::string check_glb_container(const std::string& path, std::uint64_t file_size,
                                std::string& json) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return "cannot open for reading";
  struct Closer {
    std::FILE* f;
    ~Closer() { std::fclose(f); }
  } closer{f};
  unsigned char header[12];
  if (file_size < sizeof(header) || std::fread(header, 1, sizeof(header), f) != sizeof(header))
    return "truncated GLB: " + std::to_string(file_size) +
           " bytes, shorter than the 12-byte header";
  if (read_u32_le(header) != kGlbMagic) return "corrupt GLB: bad magic (expected 'glTF')";
  const std::uint32_t version = read_u32_le(header + 4);
  if (version != 2)
    return "unsupported GLB version " + std::to_string(version) +
           " (only glTF 2.0 binary is supported)";
  const std::uint64_t length = read_u32_le(header + 8);
  if (length > file_size)
    return "truncated GLB: header declares " + std::to_string(length) + " bytes, the file has " +
           std::to_string(file_size);
  if (length < file_size)
    return "corrupt GLB: header declares " + std::to_string(length) + " bytes, the file has " +
           std::to_string(file_size);
  std::uint64_t offset = sizeof(header);
  int chunk = 0;
  while (offset < length) {
    unsigned char chunk_header[8];
    if (length - offset < sizeof(chunk_header) ||
        std::fseek(f, static_cast<long>(offset), SEEK_SET) != 0 ||
        std::fread(chunk_header, 1, sizeof(chunk_header), f) != sizeof(chunk_header))
      return "truncated GLB: chunk " + std::to_string(chunk) + " header at byte " +
             std::to_string(offset) + " is cut off";
    const std::uint64_t chunk_length = read_u32_le(chunk_header);
    const std::uint32_t type = read_u32_le(chunk_header + 4);
    const std::string name = type == kGlbChunkJson  ? "JSON"
                             : type == kGlbChunkBin ? "BIN"
                                                    : "unknown";
    if (chunk == 0 && type != kGlbChunkJson) return "corrupt GLB: the first chunk is not JSON";
    if (chunk == 0 && chunk_length == 0) return "corrupt GLB: the JSON chunk is empty";
    if (chunk_length > length - offset - sizeof(chunk_header))
      return "truncated GLB: chunk " + std::to_string(chunk) + " (" + name + ") at byte " +
             std::to_string(offset) + " declares " + std::to_string(chunk_length) +
             " bytes, only " + std::to_string(length - offset - sizeof(chunk_header)) + " remain";
    if (chunk == 0) {
      json.resize(chunk_length);
      if (std::fread(json.data(), 1, json.size(), f) != json.size())
        return "truncated GLB: the JSON chunk cannot be read";
    }
    offset += sizeof(chunk_header) + chunk_length;
    ++chunk;
  }
  if (chunk == 0) return "corrupt GLB: no JSON chunk";
  return "";
}

bool read_whole_file(const std::string& path, std::string& out) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  char buffer[1 << 16];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) out.append(buffer, n);
  const bool ok = !std::ferror(f);
  std::fclose(f);
  return ok;
}

// assimp 5.2 passes every referenced file name (a glTF buffer's uri, an OBJ's mtllib) through
// FileSystemFilter::Cleanup, which walks past the end of a name ending in "://" (found by fuzzing:
// a segfault, not an error; whitespace-only names do the same, but import_mesh always hands assimp
// a path with a directory, so composed names never are). Such names are rejected up front.
bool unusable_reference(const std::string& name) {
  return name.size() >= 3 && name.compare(name.size() - 3, 3, "://") == 0;
}

std::string quoted(const std::string& name) {
  std::string out = "'";
  for (unsigned char c : name.substr(0, 80)) {
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02x", c);
      out += hex;
    }
  }
  return out + (name.size() > 80 ? "...'" : "'");
}

// Every "uri" string value of a glTF JSON document (escapes decoded; data URIs skipped).
std::string check_gltf_uris(const std::string& json) {
  bool uri_value_next = false;
  std::size_t i = 0;
  const std::size_t n = json.size();
  while (i < n) {
    const char c = json[i];
    if (c != '"') {
      if (c != ' ' && c != '\t' && c != '\r' && c != '\n' && c != ':') uri_value_next = false;
      ++i;
      continue;
    }
    // A string token: decode it (only keys and uri values are kept).
    std::string text;
    std::size_t j = i + 1;
    for (; j < n && json[j] != '"'; ++j) {
      char ch = json[j];
      if (ch == '\\' && j + 1 < n) {
        const char e = json[++j];
        if (e == 'u' && j + 4 < n) {
          const unsigned code =
              static_cast<unsigned>(std::strtoul(json.substr(j + 1, 4).c_str(), nullptr, 16));
          ch = code < 0x80 ? static_cast<char>(code) : '?';
          j += 4;
        } else {
          ch = e == 'n'   ? '\n'
               : e == 't' ? '\t'
               : e == 'r' ? '\r'
               : e == 'b' ? '\b'
               : e == 'f' ? '\f'
                          : e;
        }
      }
      if (text.size() < 4096) text += ch;
    }
    std::size_t k = j + 1;
    while (k < n && (json[k] == ' ' || json[k] == '\t' || json[k] == '\r' || json[k] == '\n')) ++k;
    if (k < n && json[k] == ':') {
      uri_value_next = text == "uri";
      i = k + 1;
      continue;
    }
    if (uri_value_next && text.rfind("data:", 0) != 0 && unusable_reference(text))
      return "unusable file reference (uri) " + quoted(text);
    uri_value_next = false;
    i = j + 1;
  }
  return "";
}

// Every "mtllib" line of an OBJ file (with assimp's line continuations).
std::string check_obj_mtllibs(const std::string& text) {
  for (std::size_t at = text.find("mtllib"); at != std::string::npos;
       at = text.find("mtllib", at + 6)) {
    if (at > 0 && text[at - 1] != '\n' && text[at - 1] != '\r') continue;
    std::string line;
    std::size_t e = at;
    for (; e < text.size(); ++e) {
      const char c = text[e];
      if (c == '\\' && e + 1 < text.size() && (text[e + 1] == '\n' || text[e + 1] == '\r')) {
        ++e;
        continue;
      }
      if (c == '\n' || c == '\r') break;
      line += c;
    }
    // assimp ends the name at the first of these; check every prefix ending there and the whole.
    for (std::size_t p = 0; p <= line.size(); ++p)
      if ((p == line.size() || line[p] == '\0' || line[p] == '\f') &&
          unusable_reference(line.substr(0, p))) {
        const std::size_t name = std::min(line.find_first_not_of(" \t", 6), line.size());
        return "unusable material library name " + quoted(line.substr(name));
      }
  }
  return "";
}

bool is_regular_file(const char* path) {
  struct stat info {};
  return path && ::stat(path, &info) == 0 && S_ISREG(info.st_mode);
}

// The default file system, remembering every file assimp asked for and could not find (a glTF's
// .bin, an OBJ's .mtl), so a failed import can name the missing file. Only regular files are
// opened: a model referring to a FIFO or a device (/dev/stdin, /dev/zero) must not hang the import.
class RecordingIOSystem : public Assimp::DefaultIOSystem {
 public:
  bool Exists(const char* file) const override {
    const bool exists = is_regular_file(file);
    if (!exists && file) record(file);
    return exists;
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    Assimp::IOStream* stream = is_regular_file(file) ? DefaultIOSystem::Open(file, mode) : nullptr;
    if (!stream && file) record(file);
    return stream;
  }
  const std::vector<std::string>& missing() const { return missing_; }

 private:
  void record(const char* file) const {
    std::string name = file;
    while (name.rfind("./", 0) == 0) name.erase(0, 2);  // assimp probes "x" and "./x"
    if (std::find(missing_.begin(), missing_.end(), name) == missing_.end())
      missing_.push_back(name);
  }
  mutable std::vector<std::string> missing_;
};


// Destroys assimp importers (and the scenes they own) on one background thread. Freeing a scene
// costs about 20 ms per million triangles (assimp allocates every face's indices separately) and
// none of it is needed once the data has been copied out. The thread starts on first use and is
// joined, with its queue drained, when the process's statics are destroyed.
class BackgroundReleaser {
 public:
  static BackgroundReleaser& instance() {
    static BackgroundReleaser releaser;
    return releaser;
  }
  void release(std::unique_ptr<Assimp::Importer> importer) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
    queue_.push_back(std::move(importer));
    ++pending_;
    wake_.notify_one();
  }
  void wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [this] { return pending_ == 0; });
  }
  ~BackgroundReleaser() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      wake_.notify_one();
    }
    if (thread_.joinable()) thread_.join();
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, and everything has been released
      std::unique_ptr<Assimp::Importer> importer = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      importer.reset();
      lock.lock();
      if (--pending_ == 0) idle_.notify_all();
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::deque<std::unique_ptr<Assimp::Importer>> queue_;
  std::size_t pending_ = 0;
  bool stop_ = false;
  std::thread thread_;
};

// One mesh placed by one node: p_W = A p_N + b, n_W ~ N n_N.
struct Instance {
  const aiMesh* mesh = nullptr;
  unsigned mesh_index = 0;    // in the scene, for messages
  std::array<double, 9> A{};  // row-major linear part
  std::array<double, 3> b{};
  std::array<double, 9> N{};  // cofactor matrix of A times sign(det A): normals' transform
  bool flip = false;          // det A < 0: reverse winding to keep normals outward
  std::size_t vertex_offset = 0, triangle_offset = 0, triangles = 0;
  std::uint32_t material = 0;  // index into the output materials
  bool all_triangles = true;   // every face of the mesh is a triangle
};

struct WorkItem {
  std::size_t instance, begin, end;
};

struct ChunkResult {
  std::string error;
  std::size_t dropped = 0;
};

std::string describe_mesh(const aiMesh* mesh, std::size_t index) {
  std::string name = mesh->mName.length > 0 ? std::string(mesh->mName.C_Str()) : std::string();
  return name.empty() ? "mesh " + std::to_string(index) : "mesh '" + name + "'";
}

std::string format_vec(double x, double y, double z) {
  std::ostringstream out;
  out << "(" << x << ", " << y << ", " << z << ")";
  return out.str();
}

// Decodes an 8-bit RGB(A) texture; converts BGR(A) from OpenCV, gray to RGB, 16-bit to 8-bit.
bool to_texture(cv::Mat image, Texture& out) {
  if (image.empty()) return false;
  if (image.depth() == CV_16U)
    image.convertTo(image, CV_8U, 1.0 / 257.0);
  else if (image.depth() != CV_8U)
    image.convertTo(image, CV_8U);
  const int c = image.channels();
  if (c < 1 || c > 4) return false;
  out.width = image.cols;
  out.height = image.rows;
  out.channels = (c == 2 || c == 4) ? 4 : 3;
  out.pixels.resize(std::size_t(out.width) * out.height * out.channels);
  std::uint8_t* dst = out.pixels.data();
  for (int y = 0; y < image.rows; ++y) {
    const std::uint8_t* src = image.ptr<std::uint8_t>(y);
    for (int x = 0; x < image.cols; ++x, src += c) {
      if (c == 1 || c == 2) {
        dst[0] = dst[1] = dst[2] = src[0];
        if (c == 2) dst[3] = src[1];
      } else {
        dst[0] = src[2];
        dst[1] = src[1];
        dst[2] = src[0];
        if (c == 4) dst[3] = src[3];
      }
      dst += out.channels;
    }
  }
  return true;
}

// Loads the base-colour texture `reference` of a material: embedded ("*N" or an embedded file name;
// compressed bytes decoded with cv::imdecode, or raw BGRA texels) or a file relative to the model.
std::string load_texture(const aiScene* scene, const std::string& model_path,
                         const std::string& reference, Texture& out) {
  const aiTexture* embedded = scene->GetEmbeddedTexture(reference.c_str());
  if (!embedded && !reference.empty() && reference[0] == '*')
    return "embedded texture '" + reference + "' does not exist";
  if (embedded) {
    if (!embedded->pcData) return "embedded texture '" + reference + "' has no data";
    if (embedded->mHeight == 0) {
      const cv::Mat bytes(1, static_cast<int>(embedded->mWidth), CV_8UC1,
                          const_cast<aiTexel*>(embedded->pcData));
      Texture texture;
      if (!to_texture(cv::imdecode(bytes, cv::IMREAD_UNCHANGED), texture))
        return "embedded texture '" + reference + "' cannot be decoded";
      out = std::move(texture);
      return "";
    }
    out.width = static_cast<int>(embedded->mWidth);
    out.height = static_cast<int>(embedded->mHeight);
    out.channels = 4;
    const std::size_t n = std::size_t(embedded->mWidth) * embedded->mHeight;
    out.pixels.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const aiTexel& t = embedded->pcData[i];
      out.pixels[4 * i] = t.r;
      out.pixels[4 * i + 1] = t.g;
      out.pixels[4 * i + 2] = t.b;
      out.pixels[4 * i + 3] = t.a;
    }
    return "";
  }
  const std::string file = (!reference.empty() && reference[0] == '/')
                               ? reference
                               : directory_of(model_path) + reference;
  struct stat info {};
  if (::stat(file.c_str(), &info) != 0) return "texture file '" + file + "' not found";
  Texture texture;
  if (!to_texture(cv::imread(file, cv::IMREAD_UNCHANGED), texture))
    return "texture file '" + file + "' cannot be decoded";
  out = std::move(texture);
  return "";
}

// Base colour: glTF baseColorFactor (AI_MATKEY_BASE_COLOR), else the diffuse colour with the
// material's opacity as alpha.
std::array<float, 4> base_color_of(const aiMaterial* material) {
  aiColor4D color(1.0f, 1.0f, 1.0f, 1.0f);
  if (material->Get(AI_MATKEY_BASE_COLOR, color) == aiReturn_SUCCESS)
    return {color.r, color.g, color.b, color.a};
  if (material->Get(AI_MATKEY_COLOR_DIFFUSE, color) == aiReturn_SUCCESS) {
    float opacity = 1.0f;
    if (material->Get(AI_MATKEY_OPACITY, opacity) == aiReturn_SUCCESS) color.a = opacity;
    return {color.r, color.g, color.b, color.a};
  }
  return {1.0f, 1.0f, 1.0f, 1.0f};
}

// Collects (mesh, accumulated transform) pairs depth-first. Returns a problem or "".
std::string collect_instances(const aiScene* scene, const std::array<double, 12>& X_WF,
                              std::vector<Instance>& instances) {
  struct Item {
    const aiNode* node;
    std::array<double, 12> X;  // row-major 3x4: node frame -> world
    int depth;
  };
  auto compose = [](const std::array<double, 12>& P, const aiMatrix4x4& m) {
    const double C[12] = {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4};
    std::array<double, 12> R{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        R[4 * r + c] = P[4 * r] * C[c] + P[4 * r + 1] * C[4 + c] + P[4 * r + 2] * C[8 + c] +
                       (c == 3 ? P[4 * r + 3] : 0.0);
    return R;
  };
  std::vector<Item> stack{{scene->mRootNode, compose(X_WF, scene->mRootNode->mTransformation), 0}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (item.depth > kMaxNodeDepth)
      return "node hierarchy deeper than " + std::to_string(kMaxNodeDepth);
    const aiNode* node = item.node;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      if (!node->mMeshes) return "corrupt scene: node without mesh list";
      const unsigned m = node->mMeshes[k];
      if (m >= scene->mNumMeshes || !scene->mMeshes[m])
        return "corrupt scene: node references mesh " + std::to_string(m) + " of " +
               std::to_string(scene->mNumMeshes);
      Instance inst;
      inst.mesh = scene->mMeshes[m];
      inst.mesh_index = m;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) inst.A[3 * r + c] = item.X[4 * r + c];
        inst.b[r] = item.X[4 * r + 3];
      }
      const auto& a = inst.A;
      const double cof[9] = {
          a[4] * a[8] - a[5] * a[7], a[5] * a[6] - a[3] * a[8], a[3] * a[7] - a[4] * a[6],
          a[2] * a[7] - a[1] * a[8], a[0] * a[8] - a[2] * a[6], a[1] * a[6] - a[0] * a[7],
          a[1] * a[5] - a[2] * a[4], a[2] * a[3] - a[0] * a[5], a[0] * a[4] - a[1] * a[3]};
      const double det = a[0] * cof[0] + a[1] * cof[1] + a[2] * cof[2];
      inst.flip = det < 0.0;
      for (int i = 0; i < 9; ++i) inst.N[i] = inst.flip ? -cof[i] : cof[i];
      instances.push_back(inst);
    }
    if (node->mNumChildren > 0 && !node->mChildren) return "corrupt scene: node without child list";
    for (unsigned c = node->mNumChildren; c-- > 0;) {
      if (!node->mChildren[c]) return "corrupt scene: null child node";
      stack.push_back({node->mChildren[c], compose(item.X, node->mChildren[c]->mTransformation),
                       item.depth + 1});
    }
  }
  return "";
}

// Everything after the checks on path and options: returns the problem ("" on success, with
// result.mesh set); import_mesh prefixes it with the file name.
std::string import_scene(const std::string& path, const std::string& user_path,
                         const std::string& ext, const ImportOptions& options,
                         ImportResult& result) {
  auto* io = new RecordingIOSystem();  // owned by the importer
  auto owned_importer = std::make_unique<Assimp::Importer>();
  struct Release {  // small scenes are freed right here: a hand-off would cost more than it saves
    std::unique_ptr<Assimp::Importer>& importer;
    bool background;
    ~Release() {
      const aiScene* scene = importer ? importer->GetScene() : nullptr;
      if (!background || !scene) return;
      std::size_t faces = 0;
      for (unsigned m = 0; m < scene->mNumMeshes; ++m)
        faces += scene->mMeshes[m] ? scene->mMeshes[m]->mNumFaces : 0;
      if (faces >= kBackgroundCleanupFaces)
        BackgroundReleaser::instance().release(std::move(importer));
    }
  } release{owned_importer, options.background_cleanup};
  Assimp::Importer& importer = *owned_importer;
  importer.SetIOHandler(io);
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene) {
    // A file assimp needed but could not open explains the failure better than its own message.
    for (const std::string& missing : io->missing())
      if (missing != path && missing != user_path)
        return "referenced file '" + missing + "' not found";
    const std::string format = ext == ".glb"    ? "GLB"
                               : ext == ".gltf" ? "glTF"
                               : ext == ".obj"  ? "OBJ"
                                                : "STL";
    const std::string why = importer.GetErrorString() ? importer.GetErrorString() : "";
    if (why.empty()) return "cannot read " + format + ": unknown assimp error";
    if (why.rfind("No suitable reader found", 0) == 0)
      return "cannot read " + format + ": content not recognised as " + format;
    return "cannot read " + format + ": " + why;
  }
  for (const std::string& missing : io->missing())
    if (missing != path && missing != user_path)
      result.warnings.push_back(user_path + ": file '" + missing +
                                "' not found (the importer went on without it)");
  if (!scene->mRootNode) return "no triangles (the file holds no scene graph)";

  // Polygons (OBJ n-gons) become triangles; assimp's other steps are not needed.
  bool polygons = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    if (scene->mMeshes[m] && (scene->mMeshes[m]->mPrimitiveTypes & aiPrimitiveType_POLYGON))
      polygons = true;
  if (polygons) {
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
    if (!scene) return std::string("triangulation failed: ") + importer.GetErrorString();
  }

  // World-from-file transform: up-axis rotation times scale.
  const double s = options.scale;
  std::array<double, 12> X_WF{s, 0, 0, 0, 0, s, 0, 0, 0, 0, s, 0};
  if (options.up_axis == UpAxis::kY)
    X_WF = {s, 0, 0, 0, 0, 0, -s, 0, 0, s, 0, 0};  // (x,y,z)->(x,-z,y)
  std::vector<Instance> instances;
  if (std::string problem = collect_instances(scene, X_WF, instances); !problem.empty())
    return problem;

  // Sizes, offsets and the materials actually used.
  TriangleMesh mesh;
  std::vector<int> material_map(scene->mNumMaterials, -1);
  std::vector<unsigned> used_materials;
  std::size_t vertices = 0, triangles = 0;
  bool any_uvs = false, any_missing_normals = false;
  std::vector<Instance> kept;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    Instance& inst = instances[i];
    const aiMesh* m = inst.mesh;
    if (m->mNumFaces == 0 || m->mNumVertices == 0) continue;
    if (!m->mVertices || !m->mFaces)
      return "corrupt " + describe_mesh(m, inst.mesh_index) + ": missing vertex or face array";
    if (m->mPrimitiveTypes == aiPrimitiveType_TRIANGLE) {
      inst.triangles = m->mNumFaces;
    } else {
      inst.all_triangles = false;
      for (unsigned f = 0; f < m->mNumFaces; ++f) inst.triangles += m->mFaces[f].mNumIndices == 3;
    }
    if (inst.triangles == 0) continue;  // points or lines only
    if (m->mMaterialIndex >= scene->mNumMaterials && scene->mNumMaterials > 0)
      return "corrupt " + describe_mesh(m, inst.mesh_index) + ": material " +
             std::to_string(m->mMaterialIndex) + " of " + std::to_string(scene->mNumMaterials);
    if (scene->mNumMaterials > 0) {
      int& mapped = material_map[m->mMaterialIndex];
      if (mapped < 0) {
        mapped = static_cast<int>(used_materials.size());
        used_materials.push_back(m->mMaterialIndex);
      }
      inst.material = static_cast<std::uint32_t>(mapped);
    }
    inst.vertex_offset = vertices;
    inst.triangle_offset = triangles;
    vertices += m->mNumVertices;
    triangles += inst.triangles;
    any_uvs = any_uvs || m->mTextureCoords[0] != nullptr;
    any_missing_normals = any_missing_normals || m->mNormals == nullptr;
    kept.push_back(inst);
  }
  if (triangles == 0) return "no triangles (the file holds no triangle geometry)";
  if (vertices >= kDropped) return "too many vertices (" + std::to_string(vertices) + ")";

  const unsigned workers = (vertices + triangles) > 2 * kChunk ? worker_threads() : 1;
  // The arrays are zero-filled by resize; for large meshes the fill (and its page faults) is
  // spread over the workers.
  spawned_threads(workers)(5, [&](std::size_t k) {
    if (k == 0) mesh.indices.resize(3 * triangles);
    if (k == 1) mesh.positions.resize(3 * vertices);
    if (k == 2) mesh.normals.resize(3 * vertices);
    if (k == 3 && any_uvs) mesh.uvs.resize(2 * vertices);
    if (k == 4 && used_materials.size() > 1) mesh.triangle_materials.resize(triangles);
  });

  // Pass 1: vertices (transform, finiteness, normals, UVs).
  std::vector<WorkItem> items;
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (std::size_t b = 0; b < kept[i].mesh->mNumVertices; b += kChunk)
      items.push_back({i, b, std::min<std::size_t>(b + kChunk, kept[i].mesh->mNumVertices)});
  std::vector<ChunkResult> chunk_results(items.size());
  spawned_threads(workers)(items.size(), [&](std::size_t w) {
    const WorkItem& item = items[w];
    const Instance& inst = kept[item.instance];
    const aiMesh* m = inst.mesh;
    const auto& A = inst.A;
    const auto& N = inst.N;
    float* pos = mesh.positions.data() + 3 * inst.vertex_offset;
    float* nrm = mesh.normals.data() + 3 * inst.vertex_offset;
    for (std::size_t v = item.begin; v < item.end; ++v) {
      const aiVector3D& p = m->mVertices[v];
      const double x = p.x, y = p.y, z = p.z;
      const float px = static_cast<float>(A[0] * x + A[1] * y + A[2] * z + inst.b[0]);
      const float py = static_cast<float>(A[3] * x + A[4] * y + A[5] * z + inst.b[1]);
      const float pz = static_cast<float>(A[6] * x + A[7] * y + A[8] * z + inst.b[2]);
      if (!(std::isfinite(px) && std::isfinite(py) && std::isfinite(pz))) {
        chunk_results[w].error = describe_mesh(m, inst.mesh_index) + " vertex " +
                                 std::to_string(v) + " has a non-finite coordinate " +
                                 format_vec(p.x, p.y, p.z);
        return;
      }
      pos[3 * v] = px;
      pos[3 * v + 1] = py;
      pos[3 * v + 2] = pz;
    }
    if (m->mNormals) {
      for (std::size_t v = item.begin; v < item.end; ++v) {
        const aiVector3D& n = m->mNormals[v];
        const double x = N[0] * n.x + N[1] * n.y + N[2] * n.z;
        const double y = N[3] * n.x + N[4] * n.y + N[5] * n.z;
        const double z = N[6] * n.x + N[7] * n.y + N[8] * n.z;
        const double len = std::sqrt(x * x + y * y + z * z);
        if (!std::isfinite(len)) {
          chunk_results[w].error = describe_mesh(m, inst.mesh_index) + " normal " +
                                   std::to_string(v) + " is not finite " +
                                   format_vec(n.x, n.y, n.z);
          return;
        }
        const double inv = len > 0.0 ? 1.0 / len : 0.0;  // a zero normal stays zero
        nrm[3 * v] = static_cast<float>(x * inv);
        nrm[3 * v + 1] = static_cast<float>(y * inv);
        nrm[3 * v + 2] = static_cast<float>(z * inv);
      }
    }
    if (any_uvs && m->mTextureCoords[0]) {
      float* uv = mesh.uvs.data() + 2 * inst.vertex_offset;
      const aiVector3D* t = m->mTextureCoords[0];
      for (std::size_t v = item.begin; v < item.end; ++v) {
        uv[2 * v] = t[v].x;
        uv[2 * v + 1] = t[v].y;
      }
    }
  });
  for (const ChunkResult& r : chunk_results)
    if (!r.error.empty()) return r.error;

  // Pass 2: faces (index checks, winding, degenerate triangles, materials).
  items.clear();
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (kept[i].all_triangles) {
      for (std::size_t b = 0; b < kept[i].mesh->mNumFaces; b += kChunk)
        items.push_back({i, b, std::min<std::size_t>(b + kChunk, kept[i].mesh->mNumFaces)});
    } else {
      items.push_back({i, 0, kept[i].mesh->mNumFaces});  // mixed primitives: one sequential item
    }
  }
  chunk_results.assign(items.size(), {});
  spawned_threads(workers)(items.size(), [&](std::size_t w) {
    const WorkItem& item = items[w];
    const Instance& inst = kept[item.instance];
    const aiMesh* m = inst.mesh;
    const std::uint32_t nv = m->mNumVertices, base = static_cast<std::uint32_t>(inst.vertex_offset);
    const float* pos = mesh.positions.data();
    std::uint32_t* out = mesh.indices.data() + 3 * inst.triangle_offset;
    std::size_t slot = item.begin;  // all-triangle meshes: face f goes to slot f
    if (!inst.all_triangles) slot = 0;
    ChunkResult& result = chunk_results[w];
    for (std::size_t f = item.begin; f < item.end; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) {
        if (inst.all_triangles) {
          result.error = "corrupt " + describe_mesh(m, inst.mesh_index) + ": face " +
                         std::to_string(f) + " has " + std::to_string(face.mNumIndices) +
                         " indices in a triangle mesh";
          return;
        }
        continue;
      }
      if (!face.mIndices) {
        result.error = "corrupt " + describe_mesh(m, inst.mesh_index) + ": face " +
                       std::to_string(f) + " has no indices";
        return;
      }
      std::uint32_t i0 = face.mIndices[0], i1 = face.mIndices[1], i2 = face.mIndices[2];
      if (i0 >= nv || i1 >= nv || i2 >= nv) {
        result.error = "corrupt " + describe_mesh(m, inst.mesh_index) + ": face " +
                       std::to_string(f) + " uses vertex " +
                       std::to_string(std::max({i0, i1, i2})) + " of " + std::to_string(nv);
        return;
      }
      if (inst.flip) std::swap(i1, i2);
      i0 += base;
      i1 += base;
      i2 += base;
      bool degenerate = i0 == i1 || i1 == i2 || i0 == i2;
      if (!degenerate) {
        const double ax = pos[3 * i0], ay = pos[3 * i0 + 1], az = pos[3 * i0 + 2];
        const double ux = pos[3 * i1] - ax, uy = pos[3 * i1 + 1] - ay, uz = pos[3 * i1 + 2] - az;
        const double vx = pos[3 * i2] - ax, vy = pos[3 * i2 + 1] - ay, vz = pos[3 * i2 + 2] - az;
        degenerate =
            uy * vz - uz * vy == 0.0 && uz * vx - ux * vz == 0.0 && ux * vy - uy * vx == 0.0;
      }
      if (degenerate) {
        ++result.dropped;
        i0 = i1 = i2 = kDropped;
      }
      out[3 * slot] = i0;
      out[3 * slot + 1] = i1;
      out[3 * slot + 2] = i2;
      if (!mesh.triangle_materials.empty())
        mesh.triangle_materials[inst.triangle_offset + slot] = inst.material;
      ++slot;
    }
  });
  std::size_t dropped = 0;
  for (const ChunkResult& r : chunk_results) {
    if (!r.error.empty()) return r.error;
    dropped += r.dropped;
  }

  // Area-weighted vertex normals for meshes that carry none (before compaction: ranges intact).
  if (any_missing_normals) {
    std::vector<std::size_t> need;
    for (std::size_t i = 0; i < kept.size(); ++i)
      if (!kept[i].mesh->mNormals) need.push_back(i);
    spawned_threads(workers)(need.size(), [&](std::size_t k) {
      const Instance& inst = kept[need[k]];
      const float* p = mesh.positions.data();
      std::vector<double> acc(3 * inst.mesh->mNumVertices, 0.0);
      const std::uint32_t* tri = mesh.indices.data() + 3 * inst.triangle_offset;
      for (std::size_t t = 0; t < inst.triangles; ++t, tri += 3) {
        if (tri[0] == kDropped) continue;
        const std::uint32_t a = tri[0], b = tri[1], c = tri[2];
        const double ux = p[3 * b] - double(p[3 * a]), uy = p[3 * b + 1] - double(p[3 * a + 1]),
                     uz = p[3 * b + 2] - double(p[3 * a + 2]);
        const double vx = p[3 * c] - double(p[3 * a]), vy = p[3 * c + 1] - double(p[3 * a + 1]),
                     vz = p[3 * c + 2] - double(p[3 * a + 2]);
        const double n[3] = {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
        for (std::uint32_t v : {a, b, c})
          for (int d = 0; d < 3; ++d) acc[3 * (v - inst.vertex_offset) + d] += n[d];
      }
      float* out = mesh.normals.data() + 3 * inst.vertex_offset;
      for (std::size_t v = 0; v < inst.mesh->mNumVertices; ++v) {
        const double len = std::sqrt(acc[3 * v] * acc[3 * v] + acc[3 * v + 1] * acc[3 * v + 1] +
                                     acc[3 * v + 2] * acc[3 * v + 2]);
        const double inv = len > 0.0 ? 1.0 / len : 0.0;
        for (int d = 0; d < 3; ++d) out[3 * v + d] = static_cast<float>(acc[3 * v + d] * inv);
      }
    });
  }

  if (dropped > 0) {
    std::size_t kept_triangles = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
      if (mesh.indices[3 * t] == kDropped) continue;
      if (kept_triangles != t) {
        std::copy_n(&mesh.indices[3 * t], 3, &mesh.indices[3 * kept_triangles]);
        if (!mesh.triangle_materials.empty())
          mesh.triangle_materials[kept_triangles] = mesh.triangle_materials[t];
      }
      ++kept_triangles;
    }
    mesh.indices.resize(3 * kept_triangles);
    if (!mesh.triangle_materials.empty()) mesh.triangle_materials.resize(kept_triangles);
    result.degenerate_triangles_dropped = dropped;
    if (kept_triangles == 0)
      return "no triangles (all " + std::to_string(triangles) + " triangles are degenerate)";
  }

  // Materials (only those used) and their base-colour textures, each texture decoded once.
  std::map<std::string, int> texture_index;
  for (unsigned source : used_materials) {
    const aiMaterial* am = scene->mMaterials[source];
    Material material;
    if (!am) {
      mesh.materials.push_back(material);
      continue;
    }
    aiString name;
    if (am->Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS) material.name = name.C_Str();
    material.base_color = base_color_of(am);
    aiString texture_path;
    const bool has_texture =
        am->GetTexture(aiTextureType_BASE_COLOR, 0, &texture_path) == aiReturn_SUCCESS ||
        am->GetTexture(aiTextureType_DIFFUSE, 0, &texture_path) == aiReturn_SUCCESS;
    if (options.load_textures && has_texture && texture_path.length > 0) {
      const std::string reference = texture_path.C_Str();
      auto found = texture_index.find(reference);
      if (found == texture_index.end()) {
        Texture texture;
        if (std::string problem = load_texture(scene, path, reference, texture); !problem.empty())
          return "material '" + material.name + "': " + problem;
        found = texture_index.emplace(reference, static_cast<int>(mesh.textures.size())).first;
        mesh.textures.push_back(std::move(texture));
      }
      material.base_color_texture = found->second;
    }
    mesh.materials.push_back(std::move(material));
  }
  if (mesh.materials.empty()) mesh.materials.emplace_back();
  result.mesh = std::move(mesh);
  return "";
}

}  // namespace

void wait_for_background_cleanup() { BackgroundReleaser::instance().wait(); }

const std::vector<std::string>& supported_mesh_extensions() {
  static const std::vector<std::string> extensions = {".glb", ".gltf", ".obj", ".stl"};
  return extensions;
}

ImportResult import_mesh(const std::string& path, const ImportOptions& options) {
  const auto start = Clock::now();
  ImportResult result;
  auto finish = [&](const std::string& problem) -> ImportResult&& {
    if (!problem.empty()) {
      result.error = path + ": " + problem;
      result.mesh.reset();
    }
    result.load_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return std::move(result);
  };
  if (!(options.scale > 0.0) || !std::isfinite(options.scale)) {
    std::ostringstream out;
    out << "scale must be > 0 and finite (got " << options.scale << ")";
    return finish(out.str());
  }
  const std::string ext = lower_extension(path);
  const auto& supported = supported_mesh_extensions();
  if (std::find(supported.begin(), supported.end(), ext) == supported.end()) {
    std::string list;
    for (const auto& e : supported) list += (list.empty() ? "" : ", ") + e;
    return finish(
        (ext.empty() ? std::string("no file extension") : "unsupported extension '" + ext + "'") +
        " (supported: " + list + ")");
  }
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return finish("file not found");
  if (!S_ISREG(info.st_mode)) return finish("not a regular file");
  if (info.st_size == 0) return finish("file is empty");
  // Container and referenced-name checks that assimp's readers would crash on.
  if (ext == ".glb") {
    std::string json;
    if (std::string problem =
            check_glb_container(path, static_cast<std::uint64_t>(info.st_size), json);
        !problem.empty())
      return finish(problem);
    if (std::string problem = check_gltf_uris(json); !problem.empty()) return finish(problem);
  }
  if (ext == ".glb" || ext == ".gltf" || ext == ".obj") {
    // A glTF whose JSON assimp's glTF reader refuses is handed to whichever reader recognises its content:
    // the OBJ reader takes text with OBJ lines in it, mtllib names and all (a fuzzer finding: a broken
    // .gltf with "mtllib x://" crashed). So the OBJ reader's names are checked in every such file.
    std::string text;
    if (!read_whole_file(path, text)) return finish("cannot read the file");
    std::string problem = ext == ".gltf" ? check_gltf_uris(text) : "";
    if (problem.empty()) problem = check_obj_mtllibs(text);
    if (!problem.empty()) return finish(problem);
  }
  std::string problem;
  try {
    // assimp composes referenced names from the model's directory: always give it one.
    problem = import_scene(path.find('/') == std::string::npos ? "./" + path : path, path, ext,
                           options, result);
  } catch (const std::bad_alloc&) {
    problem = "out of memory while importing";
  } catch (const std::exception& e) {
    problem = std::string("import failed: ") + e.what();
  } catch (...) {
    problem = "import failed: unknown exception";
  }
  return finish(problem);
}

}  // namespace hadal::geometry

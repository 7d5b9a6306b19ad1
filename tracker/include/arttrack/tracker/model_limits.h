// Size limits of a robot description, checked right after the URDF is parsed
// (RobotModel, the simulator's preparation of the URDF for MuJoCo, a
// scenario's URDF summary), before anything costly is built from it: a
// description past them is refused in milliseconds with an InputError that
// names the file, the count and the limit, instead of running for minutes
// inside MuJoCo's compiler. docs/robots.md ("Limits") lists them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace arttrack {

struct ModelLimits {
  // <link> and <joint> elements, fixed joints and frames included. A
  // humanoid with hands has about 60 links; a dual-arm mobile manipulator
  // about 100.
  static constexpr std::size_t kMaxLinks = 1000;
  static constexpr std::size_t kMaxJoints = 1000;
  // Joints from the root link to the deepest link. The simulator nests one
  // MuJoCo body per link, and tinyxml2 (MuJoCo's XML reader and ours) reads
  // at most 100 nested elements: 95 joints in a chain is the most that loads;
  // 90 leaves room for a camera mounted on the deepest link. A humanoid's
  // deepest chain (pelvis to fingertip) has about 15.
  static constexpr int kMaxChainDepth = 90;
  // Triangles of all the meshes of a description (each use of a mesh file
  // counted): 15 times the largest shipped robot (the sculpted dual arm,
  // 330 048 visual triangles).
  static constexpr std::uint64_t kMaxMeshTriangles = 5'000'000;
  // Bytes of the URDF file itself (a 1000-link description takes about 1 MB).
  static constexpr std::uintmax_t kMaxUrdfBytes = 64u << 20;
  // Nesting of XML elements in the URDF (a URDF nests 5: robot, link,
  // visual, geometry, mesh). urdfdom's XML reader recurses once per level
  // without a bound: 200 000 nested elements (1.4 MB) overflowed the stack.
  // tinyxml2, the simulator's reader, stops at 100 too.
  static constexpr int kMaxXmlDepth = 100;
  // Bytes of one mesh file. A published robot's largest visual meshes are
  // tens of megabytes; assimp holds a file several times over while it
  // reads it.
  static constexpr std::uintmax_t kMaxMeshFileBytes = 256u << 20;
};

// Throws InputError "<source>: <n> <what> ..., more than the <limit> arttrack
// takes" when a count passes its limit; `what` is e.g. "links".
void check_model_count(const std::string& source, std::uint64_t count, std::uint64_t limit,
                       const std::string& what);

// The number of joints from the root to the deepest link of a tree given as
// child link -> parent link. Links on a loop (a tree error reported
// elsewhere) count as far as the loop; `deepest`, if given, gets the deepest
// link's name.
int chain_depth(const std::map<std::string, std::string>& parent_of,
                std::string* deepest = nullptr);

// chain_depth within ModelLimits::kMaxChainDepth, else InputError naming
// `source`, the deepest link and its depth.
void check_chain_depth(const std::string& source,
                       const std::map<std::string, std::string>& parent_of);

// The URDF file at `path` within ModelLimits::kMaxUrdfBytes, else
// InputError naming it. A missing file passes (the caller reports it).
void check_urdf_file_size(const std::filesystem::path& path);

// URDF text declares no XML entities (<!ENTITY ...>, in a DOCTYPE): URDF
// uses none, and a few nested ones expand a small file to gigabytes (the
// "billion laughs"); urdfdom then reported only that it found no <robot>.
// Its elements nest at most ModelLimits::kMaxXmlDepth deep (a light scan:
// comments, CDATA, declarations and quoted attribute values skipped).
// Throws InputError "<source>: line <n>: ..." saying what to do.
void check_urdf_text(const std::string& xml, const std::string& source);

// The triangle count a binary STL file declares (at byte 80), if the file is
// a binary STL (exactly 84 + 50 n bytes); read before the file is, so that a
// description's triangles are bounded before its meshes are loaded.
std::optional<std::uint64_t> binary_stl_triangle_count(const std::filesystem::path& path);

// Before assimp reads a mesh file (the tracker's load_mesh, the simulator's
// conversion for MuJoCo): the file within ModelLimits::kMaxMeshFileBytes,
// and a COLLADA file's geometry consistent with its own declared counts.
// assimp 5.2 trusts them: a 5 kB file whose <triangles> list was one index
// short of its count made it grow to 6 GB and more. Checked: every <source>
// array holds what its accessor reads; every <vertices> has a POSITION
// input; every primitive list (<triangles>, <polylist>, <polygons>, <lines>,
// strips and fans) has the indices its count, <vcount> and input offsets
// say, each within the items of its input's source, and at most
// ModelLimits::kMaxMeshTriangles faces in the file. Throws InputError naming
// the file, the element and its line. A missing file passes (the reader
// reports it).
void check_mesh_file(const std::filesystem::path& path);

}  // namespace arttrack

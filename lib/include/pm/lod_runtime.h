// Levels of detail at run time: a progressive mesh that an application refines and
// coarsens in place, frame by frame, at a cost proportional to the change (Hoppe 1996,
// §3-4; Hoppe 1998, "Efficient implementation of progressive meshes", §4-5).
//
// The layout is Hoppe 1998's: render vertices are wedges (a vertex with one texture
// coordinate and one normal, Hoppe 1996 §3), stored once for all levels in the order
// the splits create them; faces are stored in the order they appear, so the active faces
// of any level are a prefix of the index buffer. A vertex split rewrites one corner of
// each face it moves and lengthens the prefix; an edge collapse does the reverse. A face
// that leaves the prefix keeps its indices, which are those it is re-created with.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pm/mesh.h"
#include "pm/progressive_mesh.h"

namespace pm {

// Ownership: copies what it needs from the ProgressiveMesh (which may then go); movable and
// copyable; its per-wedge arrays never change and are shared with its geomorphs.
class RuntimeLod {
 private:
  struct Wedges;

 public:
  // pm must be valid (see validate()); the object starts at level 0, the base mesh.
  explicit RuntimeLod(const ProgressiveMesh& pm);

  // Levels as in lod.h: level k is the base mesh refined by k splits.
  std::size_t level() const { return level_; }
  std::size_t max_level() const { return splits_.size(); }

  // What a level change rewrote: entries [begin, end) of indices(). A renderer holding a copy
  // of the active indices, indices()[0, 3 * face_count()), from before the change makes it
  // the new one by uploading this range alone (Hoppe 1998, §5: the active faces are a
  // prefix, so a refinement rewrites a few corners and appends faces, a coarsening only
  // rewrites corners of the faces that stay).
  struct IndexRange {
    std::size_t begin = 0, end = 0;  // index entries, 3 per face
    bool empty() const { return begin >= end; }
  };
  // Applies the splits or collapses between the current level and the requested one.
  IndexRange set_level(std::size_t level);
  // The coarsest level with at least n faces (vertices), or whose error bound is at most e,
  // as level_for_faces / level_for_vertices / level_for_error (O(log levels)).
  IndexRange set_face_count(std::size_t n);
  IndexRange set_vertex_count(std::size_t n);
  IndexRange set_error(double e);

  // The active mesh, ready to draw: face_count() triangles of wedge indices, all below
  // wedge_count(). The wedge arrays hold every level's wedges and never change.
  std::size_t face_count() const { return face_end_[level_]; }
  std::size_t vertex_count() const;  // as vertices_at_level()
  const uint32_t* indices() const { return indices_.data(); }
  std::size_t wedge_count() const { return wedge_end_[level_]; }
  const float* positions() const;  // 3 per wedge
  // Per wedge, or null when the mesh has none (a wedge without one holds NaN).
  const float* uvs() const;
  const float* normals() const;
  const float* colors() const;
  uint32_t color_components() const;
  // Per face slot (active faces first), or null: indices into material_names().
  const uint32_t* face_materials() const;
  const std::vector<std::string>& material_names() const;
  const std::vector<std::string>& material_libraries() const;

  // The active mesh as a Mesh: one vertex per wedge in use, per-corner attributes. Its
  // faces (positions and attributes, corner by corner) are those of extract_level() at the
  // same level.
  Mesh to_mesh() const;

  // Bytes held by this object.
  std::size_t memory_bytes() const;

  // A geomorph (Hoppe 1996, §4.2) from level `from` to level `to` (from <= to): the mesh of
  // level `to`, in which each wedge that level `from` does not have starts at its
  // ancestor's position and attributes in `from`. Leaves this object at level `to`.
  // Ownership: owns its blend ends and index buffer and shares the RuntimeLod's wedge
  // arrays, so it stays valid when the RuntimeLod moves, changes level or is destroyed.
  class Geomorph {
   public:
    // Writes the blend at alpha in [0, 1] (0: level `from`'s geometry, 1: level `to`'s,
    // both exactly) into positions (3 per wedge), and uvs, normals and colours when the
    // mesh has them (each may be null), for wedges [0, wedge_count()).
    void evaluate(float alpha, float* positions, float* uvs, float* normals,
                  float* colors = nullptr) const;
    std::size_t wedge_count() const { return wedge_count_; }
    std::size_t face_count() const { return indices_.size() / 3; }
    const uint32_t* indices() const { return indices_.data(); }
    // The blended mesh as extract_level() writes a level: one vertex per vertex of level
    // `to` (welded copies merged), attributes per corner. At alpha = 1 its faces are those of
    // extract_level(to); at alpha = 0, those of extract_level(from) plus faces of no area,
    // corner attributes included (a corner has a texture coordinate or normal as level `from`
    // has it at 0, as level `to` has it above).
    Mesh mesh(float alpha) const;

   private:
    friend class RuntimeLod;
    std::size_t wedge_count_ = 0;
    std::vector<uint32_t> indices_;
    std::vector<uint32_t> morphing_;  // wedges whose start differs from their end
    std::vector<uint32_t> starts_;    // per morphing wedge: the wedge it starts as
    std::vector<float> start_positions_, end_positions_;  // 3 per morphing wedge
    std::vector<float> start_uvs_, end_uvs_, start_normals_, end_normals_;
    std::vector<float> start_colors_, end_colors_;
    std::shared_ptr<const Wedges> wedges_;
  };
  Geomorph geomorph(std::size_t from, std::size_t to);

 private:
  // What never changes after construction: the wedges' values and what to_mesh() needs.
  struct Wedges {
    std::vector<float> positions, uvs, normals, colors;
    uint32_t color_components = 0;
    std::vector<uint32_t> vertex;  // the progressive mesh's vertex id of each wedge
    std::vector<bool> has_uv, has_normal;  // per wedge, when the mesh has the kind
    std::vector<uint32_t> face_materials;  // per face slot
    std::vector<std::string> material_names, material_libraries;
    // Per base vertex when there are welds: the vertex it is output as.
    std::vector<uint32_t> canonical;
  };
  struct Split {
    uint32_t moved_begin, moved_end;  // into moved_
    uint32_t new_faces;               // 1 or 2
  };
  struct MovedCorner {
    uint32_t index;   // position in indices_: 3 * face slot + corner
    uint32_t fine;    // wedge after the split
    uint32_t coarse;  // wedge before it
  };
  void refine_to(std::size_t level);
  void coarsen_to(std::size_t level);

  std::vector<Split> splits_;
  std::vector<MovedCorner> moved_;
  std::vector<uint32_t> face_end_;   // per level: active faces
  std::vector<uint32_t> wedge_end_;  // per level: wedges in use lie below this
  std::vector<uint32_t> vertex_end_;  // per level: output vertices (vertices_at_level)
  std::vector<float> errors_;         // per level: error bound
  std::vector<uint32_t> indices_;     // 3 per face slot, all levels
  std::vector<uint32_t> wedge_parent_;  // the wedge it merges into when its vertex collapses
  std::shared_ptr<const Wedges> wedges_;  // never null
  uint32_t base_vertex_count_ = 0;
  std::size_t level_ = 0;
};

}  // namespace pm

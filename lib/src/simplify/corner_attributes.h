// Texture coordinates, normals and materials on the half-edge mesh while it is simplified
// (Hoppe 1996, "Progressive meshes", §3: each face corner refers to a "wedge" of attribute
// values, so that a vertex on a UV seam or a crease carries several).
//
// A half-edge collapse v -> u keeps u and its wedges; each corner of v that survives (in
// the faces that move from v to u) takes the wedge of u on its side of the collapsed edge.
// Seams and material borders are discontinuities to keep (Garland and Heckbert 1998, §4;
// Hoppe 1999, §5): a collapse is allowed only along them, never across, so no seam opens
// and none closes. The cost of a collapse adds the attribute error of Hoppe 1999 (see
// attribute_quadric.h), scaled to model units.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "simplify/attribute_quadric.h"
#include "simplify/half_edge_mesh.h"
#include "simplify/manifold_repair.h"
#include "pm/mesh.h"

namespace pm {

// What a collapse did to the attributes, for the vertex split that undoes it.
struct CollapseAttributes {
  // Per moved face, in the order the simplifier lists them: the corner's ids before the
  // collapse (kNoAttribute when the kind is absent).
  std::vector<uint32_t> moved_uvs, moved_normals;
  // The removed faces' corners before the collapse: fl as (v, u, vl), then fr as (u, v, vr).
  std::vector<uint32_t> new_face_uvs, new_face_normals;
};

class CornerAttributes {
 public:
  // Takes the input's corner ids for each half-edge-mesh face (repaired.input_face).
  CornerAttributes(const Mesh& input, const ManifoldMesh& repaired);

  bool has_uvs() const { return kinds_[kUv].present; }
  bool has_normals() const { return kinds_[kNormal].present; }
  // The input has materials (even if every face was carried aside and none is here).
  bool has_materials() const { return has_materials_; }
  bool any() const { return has_uvs() || has_normals() || has_materials(); }

  // An interior edge whose two faces differ in material, or in a corner's texture
  // coordinates or normal at either end (compared by value, bit for bit).
  bool is_seam(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) const;
  // Texture-coordinate seams only (SeamDrift follows them).
  bool is_uv_seam(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) const;

  // For each kind, the collapse h = (v -> u) is legal when v is on no seam of that kind,
  // or on exactly two of its seam edges, one of them v-u (v slides along the seam), and
  // when u's two sides of v-u differ only if v's do. And no face that moves turns its
  // texture-space winding over or flat (Hoppe 1996, §3 keeps attributes; this keeps the
  // texture from folding).
  bool collapse_keeps_attributes(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) const;

  // The attribute error of the collapse in squared model units: for each kind, v's wedges'
  // quadrics at u's position and at the values the corners take, as a mean over their
  // area, times the kind's scale squared.
  double collapse_cost(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) const;

  // Applies the collapse to the corners (call before mesh.collapse(h), once the collapse
  // is decided): appends what the split needs to `record`; the moved faces are v's faces
  // other than fl and fr, in vf_range order.
  void collapse(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h,
                CollapseAttributes& record);

  // The current corner ids of face f at the given vertices (in that order).
  void corner_ids(HalfEdgeMesh::FaceHandle f, const HalfEdgeMesh::VertexHandle (&at)[3],
                  uint32_t (&uvs)[3], uint32_t (&normals)[3]) const;
  uint32_t material(HalfEdgeMesh::FaceHandle f) const {
    return material_.empty() ? kNoAttribute : material_[f.idx()];
  }

 private:
  static constexpr int kUv = 0, kNormal = 1, kKinds = 2;
  struct Kind {
    bool present = false;
    int dims = 0;
    const std::vector<float>* values = nullptr;  // the input's table
    std::vector<uint32_t> value_class;  // id -> smallest id with the same value bits
    std::vector<std::array<uint32_t, 3>> ids;    // per face, per corner
    std::vector<std::array<uint32_t, 3>> wedge;  // per face, per corner: quadric slot
    double scale = 0;  // model units per attribute unit
    uint32_t class_of(uint32_t id) const { return id == kNoAttribute ? id : value_class[id]; }
    const float* value(uint32_t id) const { return values->data() + std::size_t{id} * dims; }
  };
  // Which corner of face f holds vertex w (0, 1 or 2).
  int corner_of(HalfEdgeMesh::FaceHandle f, HalfEdgeMesh::VertexHandle w) const;
  uint32_t class_at(int kind, HalfEdgeMesh::FaceHandle f, HalfEdgeMesh::VertexHandle w) const {
    return kinds_[kind].class_of(kinds_[kind].ids[f.idx()][corner_of(f, w)]);
  }
  bool is_seam_of_kind(int kind, const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) const;
  bool kind_allows(int kind, const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) const;
  bool keeps_uv_winding(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) const;
  // The corner of u whose wedge a corner of v with class c takes: u's corner in fl when c
  // is v's class in fl, else in fr. Returns {face, corner index}.
  std::pair<HalfEdgeMesh::FaceHandle, int> target_corner(int kind, const HalfEdgeMesh& mesh,
                                                        HalfEdgeMesh::HalfedgeHandle h,
                                                        uint32_t v_class) const;
  void initialize_wedges(int kind, const HalfEdgeMesh& mesh);

  std::vector<std::array<uint32_t, 3>> vertex_;  // per face: the vertex of each corner
  Kind kinds_[kKinds];
  std::vector<uint32_t> material_;  // per face, or empty
  bool has_materials_ = false;
  std::vector<AttributeQuadric<2>> uv_quadrics_;
  std::vector<AttributeQuadric<3>> normal_quadrics_;
};

}  // namespace pm

// The collapse loop's attribute error (lib/src/simplify/corner_attributes.h): Hoppe 1999's
// (§4: each face's attribute as a linear function of position, read at u against the value
// the corner takes) over v's faces as they are now (memoryless, Lindstrom and Turk 1998, §3).
// On a literal fan, its value exactly; and that a collapse elsewhere leaves no trace in it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "pm/mesh.h"
#include "simplify/corner_attributes.h"
#include "simplify/face_renumbering.h"

namespace pm {
namespace {

// A kite of four faces around vertex 0 at the origin, in the plane z = 0: vertices 1 to 4 at
// (1, 0), (0, 1), (-2, 0), (0, -1), so that the faces' areas are 0.5, 1, 1 and 0.5. Its
// texture coordinates are uv = 0.5 + 0.25 p, one entry per vertex (no seam), but for vertex
// 0, whose u is `raised` above that.
Mesh kite(float raised) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, -2, 0, 0, 0, -1, 0};
  mesh.triangles = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};
  for (std::size_t x = 0; x < 5; ++x) {
    mesh.uvs.push_back(0.5f + 0.25f * mesh.positions[3 * x]);
    mesh.uvs.push_back(0.5f + 0.25f * mesh.positions[3 * x + 1]);
  }
  mesh.uvs[0] += raised;
  mesh.uv_indices = mesh.triangles;
  return mesh;
}

// The mesh's triangles are the loop's faces: CornerAttributes reads their vertices there,
// and a test that collapses moves them itself, as the loop does (move_corners()).
CornerAttributes attributes_of(const Mesh& mesh) {
  return CornerAttributes(mesh, FaceVertices{mesh.triangles.data(), 1}, mesh.face_count(),
                          mesh.positions.data(), mesh.vertex_count(), nullptr, nullptr);
}

// The loop's part of the collapse v -> u, after CornerAttributes::collapse(): the faces that
// stay take u for v.
void move_corners(Mesh& mesh, uint32_t v, uint32_t u, const std::vector<uint32_t>& moved) {
  for (const uint32_t f : moved)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[3 * f + k] == v) mesh.triangles[3 * f + k] = u;
}

Vec3 position(const Mesh& mesh, uint32_t x) {
  return Vec3(mesh.positions[3 * x], mesh.positions[3 * x + 1], mesh.positions[3 * x + 2]);
}

// The collapse v -> u over the faces `faces` (v's), fl = (v, u, vl) and fr = (u, v, vr).
struct Star {
  std::vector<uint32_t> faces;
  CollapseStar c{};
  Star(const Mesh& mesh, uint32_t v, uint32_t u, uint32_t fl, uint32_t vl, uint32_t fr,
       uint32_t vr, std::vector<uint32_t> v_faces)
      : faces(std::move(v_faces)) {
    c.v = v, c.u = u, c.fl = fl, c.vl = vl, c.fr = fr, c.vr = vr;
    c.pu = position(mesh, u), c.pv = position(mesh, v);
    c.faces = faces.data();
    c.n_faces = static_cast<int>(faces.size());
    c.seamless = true;
  }
};

// Vertex 0 onto vertex 1: fl = face 0 (0, 1, 2), fr = face 3 (0, 4, 1) = (1, 0, 4).
double cost_of_0_onto_1(const Mesh& mesh, const CornerAttributes& attributes) {
  const Star star(mesh, 0, 1, 0, 2, 3, 4, {0, 1, 2, 3});
  return attributes.collapse_cost(star.c);
}

TEST(CornerAttributes, AnAttributeLinearOverTheFacesCostsNothing) {
  const Mesh mesh = kite(0.0f);
  EXPECT_EQ(cost_of_0_onto_1(mesh, attributes_of(mesh)), 0.0);
}

// Raised by r, vertex 0's u makes each face's function 0.5 + 0.25 x + r * phi(p), phi its hat
// function at vertex 0. At u = (1, 0): phi is 0 on fl and fr, which hold u, and 1.5 on the
// other two faces (1 + x / 2 - y and 1 + x / 2 + y): an error of 2.25 r^2 on each, whose
// areas are 1, so a mean of 4.5 r^2 / 3 over the four faces' areas (unweighted, 1.125 r^2).
// Times the texture's scale squared, the surface's area per unit of texture area:
// 3 / 0.1875 = 16. So 24 r^2.
TEST(CornerAttributes, TheCostIsTheFacesDeviationAtUAsAMeanOverTheirArea) {
  for (const float raised : {0.015625f, 0.03125f, 0.0625f}) {  // exact in float
    SCOPED_TRACE(raised);
    const Mesh mesh = kite(raised);
    const double r = raised;
    EXPECT_NEAR(cost_of_0_onto_1(mesh, attributes_of(mesh)), 24 * r * r, 1e-12);
  }
}

// A hexagonal fan of six faces around vertex 0, vertices 1 to 6 at (2, 0), (1, 2), (-1, 2),
// (-2, 0), (-1, -2), (1, -2), with uv = 0.5 + 0.125 p but for vertex 0's u, raised by 1/16.
Mesh hexagon(const std::vector<uint32_t>& triangles) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 2, 0, 0, 1, 2, 0, -1, 2, 0, -2, 0, 0, -1, -2, 0, 1, -2, 0};
  mesh.triangles = triangles;
  for (std::size_t x = 0; x < 7; ++x) {
    mesh.uvs.push_back(0.5f + 0.125f * mesh.positions[3 * x]);
    mesh.uvs.push_back(0.5f + 0.125f * mesh.positions[3 * x + 1]);
  }
  mesh.uvs[0] += 0.0625f;
  mesh.uv_indices = mesh.triangles;
  return mesh;
}

// Memoryless: after vertex 2 collapses onto vertex 1 (face 0 goes, face 1 becomes (0, 1, 3)),
// vertex 0's cost is the one a mesh made of the faces left gives; the faces that went count
// for nothing (a sum of the input faces' errors, as quadrics keep, would still hold them).
TEST(CornerAttributes, ACollapseElsewhereLeavesNoTraceInTheCost) {
  Mesh mesh = hexagon({0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 1});
  CornerAttributes attributes = attributes_of(mesh);
  // 0 -> 1: fl = face 0 (0, 1, 2), fr = face 5 (0, 6, 1) = (1, 0, 6).
  const double before = attributes.collapse_cost(Star(mesh, 0, 1, 0, 2, 5, 6, {0, 1, 2, 3, 4, 5}).c);
  // 2 -> 1 along the border: no face holds 2 -> 1; fr = face 0 = (1, 2, 0), vr = 0.
  const Star border(mesh, 2, 1, CollapseStar::kNoFace, 0, 0, 0, {0, 1});
  CollapseAttributes record;
  record.make_room(true, false, 1);
  attributes.collapse(border.c, record);
  move_corners(mesh, 2, 1, {1});
  // 0 -> 1 now: fl = face 1 (0, 1, 3), fr = face 5.
  const double after = attributes.collapse_cost(Star(mesh, 0, 1, 1, 3, 5, 6, {1, 2, 3, 4, 5}).c);

  // The faces left, in their order and with their corners' order.
  const Mesh left = hexagon({0, 1, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 1});
  const double fresh =
      attributes_of(left).collapse_cost(Star(left, 0, 1, 0, 3, 4, 6, {0, 1, 2, 3, 4}).c);
  // The same faces' errors; the texture's scale, the whole input's, the same ratio of areas
  // (the map is linear at the border), summed in another order.
  EXPECT_NEAR(after, fresh, 1e-12 * fresh);
  EXPECT_GT(fresh, 0.0);
  EXPECT_GT(std::abs(after - before), 0.01 * before);
}

// The hexagon with one material per face (10 to 15), after the collapse 2 -> 1 along the
// border: face 0 goes, face 1 becomes (0, 1, 3) with vertex 1's ids. The attributes read the
// mesh's triangles, which the collapse updated as the loop does.
struct CollapsedHexagon {
  Mesh mesh = with_materials(hexagon({0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 1}));
  CornerAttributes attributes = attributes_of(mesh);
  CollapsedHexagon() {
    const Star border(mesh, 2, 1, CollapseStar::kNoFace, 0, 0, 0, {0, 1});
    CollapseAttributes record;
    record.make_room(true, false, 1);
    attributes.collapse(border.c, record);
    move_corners(mesh, 2, 1, {1});
  }
  static Mesh with_materials(Mesh mesh) {
    mesh.face_materials = {10, 11, 12, 13, 14, 15};
    mesh.material_names = {"m"};
    return mesh;
  }
};

// finish() keeps what the assembly reads, renamed to the caller's ids: the live faces'
// corners, and every face's material (the faces a collapse removed too: their splits
// restore them).
TEST(CornerAttributes, FinishKeepsTheLiveFacesCornersAndEveryMaterialInTheCallersIds) {
  CollapsedHexagon collapsed;
  CornerAttributes& attributes = collapsed.attributes;
  attributes.end_collapses();
  // The caller's ids: faces reversed, vertices shifted by one (mod 7).
  const std::vector<uint32_t> face_of = {5, 4, 3, 2, 1, 0};
  const std::vector<uint32_t> vertex_of = {1, 2, 3, 4, 5, 6, 0};
  const std::vector<uint8_t> face_dead = {1, 0, 0, 0, 0, 0};
  attributes.finish(face_of, vertex_of, face_dead);
  for (uint32_t f = 0; f < 6; ++f) EXPECT_EQ(attributes.material(face_of[f]), 10 + f);
  // Face 1, now (0, 1, 3), is the caller's face 4 with vertices (1, 2, 4); its corners keep
  // their texture coordinates' ids: vertex 0's, vertex 1's (taken from u) and vertex 3's.
  uint32_t uvs[3], normals[3];
  attributes.corner_ids(4, {2, 4, 1}, uvs, normals);
  EXPECT_EQ(uvs[0], 1u);
  EXPECT_EQ(uvs[1], 3u);
  EXPECT_EQ(uvs[2], 0u);
  EXPECT_EQ(normals[0], kNoAttribute);
  // Face 5 (0, 6, 1), the caller's 0, with vertices (1, 0, 2).
  attributes.corner_ids(0, {1, 0, 2}, uvs, normals);
  EXPECT_EQ(uvs[0], 0u);
  EXPECT_EQ(uvs[1], 6u);
  EXPECT_EQ(uvs[2], 1u);
}

// compact(): the faces renamed without the dead ones (face 0, after 2 -> 1), as the loop
// does between rounds. The costs read the same faces under their new ids, and finish() still
// gives every face's material, the dead face's (kept aside by compact()) too, and the live
// faces' corners, in the caller's ids.
TEST(CornerAttributes, RenamedFacesKeepTheirCostsCornersAndMaterials) {
  CollapsedHexagon collapsed;
  Mesh& mesh = collapsed.mesh;
  CornerAttributes& attributes = collapsed.attributes;
  // 0 -> 1: fl = face 1 (0, 1, 3), fr = face 5 (1, 0, 6).
  const double before = attributes.collapse_cost(Star(mesh, 0, 1, 1, 3, 5, 6, {1, 2, 3, 4, 5}).c);
  // The caller's ids of the loop's faces, before the renaming: faces reversed.
  const std::vector<uint32_t> given = {5, 4, 3, 2, 1, 0};
  const FaceRenumbering faces(std::vector<uint8_t>{1, 0, 0, 0, 0, 0});
  attributes.compact(faces, given.data());
  faces.compact(mesh.triangles, 3);  // the loop renames its own faces as well
  // The same collapse, its faces one id lower.
  const double after = attributes.collapse_cost(Star(mesh, 0, 1, 0, 3, 4, 6, {0, 1, 2, 3, 4}).c);
  EXPECT_EQ(after, before);
  EXPECT_GT(after, 0.0);

  attributes.end_collapses();
  const std::vector<uint32_t> face_of = {4, 3, 2, 1, 0};  // the live faces' caller ids
  const std::vector<uint32_t> vertex_of = {0, 1, 2, 3, 4, 5, 6};
  attributes.finish(face_of, vertex_of, std::vector<uint8_t>(5, 0));
  // The caller's face 5 is the dead one, material 10.
  for (uint32_t f = 0; f < 6; ++f) EXPECT_EQ(attributes.material(given[f]), 10 + f);
  // The loop's face 1, renamed 0 and the caller's 4, is (0, 1, 3) with vertex 1's ids at 1.
  uint32_t uvs[3], normals[3];
  attributes.corner_ids(4, {0, 1, 3}, uvs, normals);
  EXPECT_EQ(uvs[0], 0u);
  EXPECT_EQ(uvs[1], 1u);
  EXPECT_EQ(uvs[2], 3u);
}

}  // namespace
}  // namespace pm

// May this half-edge collapse happen? Separate from its cost, and pure: nothing changes.
#pragma once

#include "half_edge_mesh.h"

namespace pm {

// Topology: the collapse h = (v -> u) keeps the mesh a manifold of the same genus and
// number of boundary loops. That is the link condition (Dey, Edelsbrunner, Guha and
// Nekhayev 1999, "Topology preserving edge contraction", §2: the common neighbours of v
// and u are exactly vl and vr) plus the boundary rules of Hoppe et al. 1993 ("Mesh
// optimization", §3.2: an interior edge between two boundary vertices may not collapse),
// as checked by OpenMesh's is_collapse_ok; and no closed tetrahedron is flattened.
bool collapse_keeps_topology(HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h);

// Geometry: no face of v's fan that survives turns its normal by more than the angle
// whose cosine is cos_max_flip, and none becomes degenerate (its area vector shrinks to
// a negligible fraction of its squared longest edge).
bool collapse_keeps_geometry(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h,
                             double cos_max_flip);

}  // namespace pm

// The error of removing a vertex, by Schroeder's decimation criteria (Schroeder, Zarge
// and Lorensen 1992, §3.2 "Evaluating the decimation criteria"; Schroeder 1997, §3.3).
#pragma once

#include "simplify/half_edge_mesh.h"
#include "simplify/vertex_classification.h"

namespace pm {

// Simple vertex: distance from v to the average plane of its triangles, whose normal is
// the area-weighted mean of the face normals and which passes through the area-weighted
// mean of the face centres (Schroeder 1992, §3.2).
double distance_to_average_plane(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                                 HalfEdgeMesh::VertexHandle v);

// Boundary and interior-edge vertex: distance from v to the line through its two
// boundary or feature neighbours (Schroeder 1992, §3.2).
double distance_to_feature_line(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v,
                                const VertexClass& vertex_class);

// The true error of the half-edge collapse h = (v -> u), used for corners: the distance
// from v to the triangles that replace v's fan (v's faces with v moved onto u, less the
// two that vanish), or to the edges u-vl / u-vr when no face remains.
double collapse_distance(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h);

// The error Schroeder's criteria assign to removing v along h, by its kind.
double vertex_removal_error(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                            const VertexClass& vertex_class, HalfEdgeMesh::HalfedgeHandle h);

}  // namespace pm

// The half-edge mesh the simplifier works on: OpenMesh's triangle mesh with float
// points (positions never change under half-edge collapses) and status bits, which
// OpenMesh's collapse() needs to mark deleted elements.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace pm {

struct HalfEdgeTraits : public OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
};
using HalfEdgeMesh = OpenMesh::TriMesh_ArrayKernelT<HalfEdgeTraits>;

}  // namespace pm

// meshoptimizer on the vertex buffer a renderer gets: the peer of pmenc's attribute-aware
// LODs in the UV benchmark (issue 4).
//
// A GPU vertex holds one position, one UV and one normal, so a glTF exporter splits every
// vertex on a UV seam or a crease into one copy per distinct (position, uv, normal) triple.
// meshopt_simplify (meshoptimizer 0.18)
// finds the copies by their equal positions and treats them as seam vertices, which may
// only collapse along the seam (meshoptimizer src/simplifier.cpp, "kSeam"); 0.18 has no
// meshopt_simplifyWithAttributes, so the UVs themselves play no part in its cost.
#pragma once

#include <cstddef>

#include "pm/mesh.h"

namespace pm::bench {

struct MeshoptLod {
  // The simplified mesh, one vertex per seam-split copy that is still used; every corner of
  // a copy has the copy's UV and normal. Colours are carried per copy; materials are not
  // (meshopt does not say which input face an output face came from).
  pm::Mesh lod;
  double milliseconds = 0;  // the meshopt_simplify calls alone
};

// Splits `original` by (position, uv, normal) index triple and runs meshopt_simplify on the
// whole buffer, one primitive, to 3 x target_faces indices with options 0 and no error
// limit (target_error FLT_MAX), as the quality benchmark runs it. Materials are not passed
// on: a material border that is no UV seam or crease is not held (one per material, each
// primitive's border would be free to move and the surface would tear between them).
MeshoptLod meshopt_seam_split_lod(const pm::Mesh& original, std::size_t target_faces);

}  // namespace pm::bench

// Levels of detail of a progressive mesh: which level answers a request, and the
// mesh at a level. Level k is the base mesh refined by the first k splits; level
// split_count() is the input, exactly.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "pm/mesh.h"
#include "pm/progressive_mesh.h"

namespace pm {

// Faces and vertices output at level k (welded copies not counted; loose vertices only
// at full detail; carried faces at every level).
std::size_t faces_at_level(const ProgressiveMesh& pm, std::size_t level);
std::size_t vertices_at_level(const ProgressiveMesh& pm, std::size_t level);
// Error bound of level k (0 at full detail).
float error_at_level(const ProgressiveMesh& pm, std::size_t level);

// The coarsest level with at least n faces (vertices); split_count() when n exceeds the input's.
std::size_t level_for_faces(const ProgressiveMesh& pm, std::size_t n);
std::size_t level_for_vertices(const ProgressiveMesh& pm, std::size_t n);
// The coarsest level whose error bound is at most e.
std::size_t level_for_error(const ProgressiveMesh& pm, double e);

// The mesh at a level, with welded copies merged back and unused vertices dropped.
// pm must be valid (see validate()); level is clamped to split_count().
Mesh extract_level(const ProgressiveMesh& pm, std::size_t level);

// Several levels in one walk over the splits (pmdec --lods): calls emit(level, mesh) for
// each distinct level, coarse to fine, with the mesh extract_level() gives for it.
void extract_levels(const ProgressiveMesh& pm, std::vector<std::size_t> levels,
                    const std::function<void(std::size_t, const Mesh&)>& emit);

}  // namespace pm

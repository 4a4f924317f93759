// Stages of encode()'s pipeline on a progressive mesh (pm/encoder.h runs them in this order
// after the simplifier): the splits' layers inside the .pm stream's chunks, then the
// attribute tables' order. Not part of the data model (pm/progressive_mesh.h): for tools and
// tests that build or reorder a ProgressiveMesh themselves; an embedder who calls encode()
// and write_pm() needs none of it.
#pragma once

#include <cstdint>
#include <vector>

#include "pm/progressive_mesh.h"

namespace pm {

// The .pm stream's chunks (pm-format.md §5.6): 256 splits, then doubling up to `largest`,
// the rest in the last. Sizes, in order.
std::vector<uint32_t> chunk_plan(uint32_t splits, uint32_t largest);

// Reorders the splits of each chunk of chunk_plan(splits, largest_chunk) into layers of
// splits that do not depend on each other, each layer by u's id (Pajarola and Rossignac
// 2000, "Compressed progressive meshes", §3), renumbering vertex and face ids to match; the
// mesh at the end of every chunk is unchanged. A split's error becomes the largest original
// error from it to the end of its chunk. pm must be valid; it stays valid.
//
// share > 0 (and finite) bounds the reordering further: the splits are layered in windows
// inside the chunks, each of at most share times the vertices before it (but at least
// kLeastLayerWindow), so that a level inside a window has as many vertices as the greedy
// level it replaces, and an error bound no larger than the greedy level's at the window's
// start, a share fewer vertices away.
// On two threads when `threads` allows (0: the machine's cores) and there are many splits;
// the same result on any number.
void layer_splits(ProgressiveMesh& pm, uint32_t largest_chunk, double share = 0,
                  unsigned threads = 1);

// Renumbers the texture-coordinate and normal tables in the order in which a decoder first
// meets their entries (corner order, pm-format.md §5.1), entries no corner uses last, which
// is what the .pm stream codes cheapest (§5.11). Nothing when pm keeps the input's order
// (its full detail lists the tables as the input did). pm must be valid; it stays valid,
// and every level's corners keep their values.
void order_attribute_tables(ProgressiveMesh& pm);

// The windows layer_splits reorders within, in order: their sizes.
inline constexpr uint32_t kLeastLayerWindow = 1;
std::vector<uint32_t> layer_windows(uint32_t base_vertices, uint32_t splits, uint32_t largest_chunk,
                                    double share);

}  // namespace pm

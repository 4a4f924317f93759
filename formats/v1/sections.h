// Format 1.x's sections (pm-format-1.md §4, §5): the ones this reader knows, in the order a
// stream holds them, the counts their sizes follow from, and each one's encoder and decoder
// (sections.cpp), which pm_codec_v1.cpp calls by section. Internal to formats/.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "byte_io.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"

namespace pm::detail::v1 {

// The sections this reader knows, in the order a stream must hold them (§4.3).
enum KnownSection {
  kBase,
  kSplits,
  kWelds,
  kCarried,
  kLoose,
  kColors,  // 1.1: the attribute sections
  kUvs,
  kNormals,
  kMaterials,
  kKnownSectionCount
};
constexpr int kFirstAttributeSection = kColors;
constexpr std::array<uint32_t, kKnownSectionCount> kKnownTags = {
    kTagBase,   kTagSplits, kTagWelds,   kTagCarried,  kTagLoose,
    kTagColors, kTagUvs,    kTagNormals, kTagMaterials};

inline bool is_attribute_section(int section) {
  return section >= kFirstAttributeSection;
}

// V, T and the number of corner codes of UVS0 and NRML (§1).
inline uint64_t all_vertices(const Header& h) {
  return uint64_t{h.base_vertex_count} + h.split_count + h.loose_vertex_count;
}
inline uint64_t all_faces(const Header& h) {
  return uint64_t{h.base_face_count} + h.split_face_count + h.carried_face_count;
}
inline uint64_t corner_codes(const Header& h) {
  return 3 * all_faces(h) + h.moved_face_count;
}

using SectionEncoder = std::string (*)(const ProgressiveMesh&);
using SectionDecoder = bool (*)(ByteReader&, const Header&, ProgressiveMesh&);
// The encoder and the decoder of each known section, by KnownSection (sections.cpp).
extern const std::array<SectionEncoder, kKnownSectionCount> kEncoders;
extern const std::array<SectionDecoder, kKnownSectionCount> kDecoders;

}  // namespace pm::detail::v1

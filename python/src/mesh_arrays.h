// The mesh as plain numpy arrays (pmesh.Mesh), both ways:
// - out of the library without copies: a pm::Mesh moves to the heap and the arrays are views
//   of its vectors, kept alive by a capsule that owns it;
// - into the library after checks (dtype, shape, finite values, indices in range) that name
//   the array and the first bad row, made before any library call runs.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pm/mesh.h"
#include "pm/mesh_view.h"

namespace pmesh {

namespace py = pybind11;

// pmesh.Mesh. Every attribute is a numpy array or None (lists of str for the materials):
//   positions (n, 3) float32; faces (m, 3) uint32 (counter-clockwise);
//   uvs (k, 2) float32 with uv_indices (m, 3) uint32, one per corner;
//   normals (j, 3) float32 with normal_indices (m, 3) uint32;
//   colors (n, 3 or 4) float32, one per vertex;
//   face_materials (m,) uint32 into material_names; material_libraries (OBJ mtllib).
// A corner or face without the attribute holds NO_ATTRIBUTE (0xFFFFFFFF).
struct Mesh {
  py::object positions = py::none(), faces = py::none(), uvs = py::none(), uv_indices = py::none(),
             normals = py::none(), normal_indices = py::none(), colors = py::none(),
             face_materials = py::none();
  py::list material_names, material_libraries;

  // When the arrays are views of a mesh the library produced (read, level, ...): that mesh,
  // and the arrays as they were made. While each attribute is still the same array, the
  // library mesh goes back in without a copy (an array written in place is that mesh's own
  // memory).
  std::shared_ptr<const pm::Mesh> source;
  std::vector<PyObject*> source_arrays;
};

// The Python mesh over a library mesh, without copying its arrays.
Mesh wrap_mesh(pm::Mesh&& mesh);

// Checks a Python mesh (raises pmesh.Error, code invalid-argument, naming `what` and the
// array: "positions: expected float32, got float64") and returns the library mesh it stands
// for: `mesh.source` itself when its arrays are unchanged, else a copy in `storage`.
const pm::Mesh& library_mesh(const Mesh& mesh, const char* what, pm::Mesh& storage);

// A Python mesh as the library's input for encode(), after the same checks as library_mesh():
// either `mesh` (the library mesh its arrays are still views of) or `view`, views of the
// caller's numpy arrays (pm/mesh_view.h) without a copy: an array whose rows hold packed
// values (C-contiguous, or rows a stride apart as in a column slice of a wider array) is
// passed as it is; only one of another layout (columns apart, rows backwards) is copied,
// into `storage`. The numpy arrays must outlive the call that reads `view` (the Python
// Mesh holds them).
struct LibraryInput {
  LibraryInput() = default;
  LibraryInput(const LibraryInput&) = delete;  // view points into it: never moved
  LibraryInput& operator=(const LibraryInput&) = delete;
  const pm::Mesh* mesh = nullptr;
  pm::MeshView view;
  std::size_t faces = 0;
  std::size_t copied_arrays = 0;  // arrays copied into storage for their layout
  std::vector<std::string> material_names, material_libraries;
  std::vector<float> float_storage[4];
  std::vector<uint32_t> index_storage[4];
};
void library_input(const Mesh& mesh, const char* what, LibraryInput& out);

// A read-only or writable numpy view of `count` rows of `columns` T at `data`, which
// `owner` keeps alive. columns == 0: a one-dimensional array.
template <class T>
py::array_t<T> view(const T* data, std::size_t count, std::size_t columns, py::handle owner,
                    bool writable) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(count)};
  if (columns) shape.push_back(static_cast<py::ssize_t>(columns));
  static const T kNone[1] = {};
  // numpy allocates (copies) when given no pointer: an empty vector's data() may be null.
  py::array_t<T> array(shape, data ? data : kNone, owner);
  if (!writable) array.attr("flags").attr("writeable") = false;
  return array;
}

// Registers pmesh.Mesh.
void register_mesh(py::module_& m);

}  // namespace pmesh

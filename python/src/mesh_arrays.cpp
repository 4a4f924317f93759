#include "mesh_arrays.h"

#include <cmath>
#include <cstring>
#include <initializer_list>

#include "errors.h"

namespace pmesh {

namespace {

// The array attributes of a Mesh, in one order.
std::vector<PyObject*> array_pointers(const Mesh& mesh) {
  return {mesh.positions.ptr(), mesh.faces.ptr(),   mesh.uvs.ptr(),    mesh.uv_indices.ptr(),
          mesh.normals.ptr(),   mesh.normal_indices.ptr(), mesh.colors.ptr(),
          mesh.face_materials.ptr()};
}

// An argument read as rows of T, through its strides (any layout numpy has), after its dtype
// and shape are checked. `array` keeps the memory alive while the rows are read.
template <class T>
struct Rows {
  py::array array;
  const char* data = nullptr;
  std::size_t count = 0, columns = 0;
  py::ssize_t row_stride = 0, column_stride = 0;
  bool present = false;

  T at(std::size_t row, std::size_t column) const {
    T value;
    std::memcpy(&value, data + py::ssize_t(row) * row_stride + py::ssize_t(column) * column_stride,
                sizeof value);
    return value;
  }
  // Appends the rows to `out`, row by row.
  void append_to(std::vector<T>& out) const {
    out.reserve(out.size() + count * columns);
    if (row_stride == py::ssize_t(columns * sizeof(T)) && (columns <= 1 || column_stride == sizeof(T))) {
      const T* first = reinterpret_cast<const T*>(data);
      out.insert(out.end(), first, first + count * columns);
      return;
    }
    for (std::size_t r = 0; r < count; ++r)
      for (std::size_t c = 0; c < columns; ++c) out.push_back(at(r, c));
  }
};

template <class T>
const char* expected_dtype();
template <>
const char* expected_dtype<float>() {
  return "float32";
}
template <>
const char* expected_dtype<uint32_t>() {
  return "uint32";
}

std::string shape_text(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d)
    text += (d ? ", " : "") + std::to_string(array.shape(d));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

// `value` as rows of T with one of `columns` columns (0: a one-dimensional array); None
// gives no rows (present false). Raises naming `name` on a wrong type, dtype or shape.
template <class T>
Rows<T> rows_of(const py::object& value, const std::string& name,
                std::initializer_list<std::size_t> columns) {
  Rows<T> rows;
  if (value.is_none()) return rows;
  if (!py::isinstance<py::array>(value))
    invalid_argument(name + ": expected a numpy array of " + expected_dtype<T>() + ", got " +
                     std::string(py::str(value.get_type().attr("__name__"))));
  rows.array = py::reinterpret_borrow<py::array>(value);
  if (!py::isinstance<py::array_t<T>>(value))
    invalid_argument(name + ": expected dtype " + expected_dtype<T>() + ", got " +
                     std::string(py::str(rows.array.dtype())) + " (convert with .astype(numpy." +
                     expected_dtype<T>() + "))");
  const std::size_t wanted_columns = *columns.begin();
  bool shape_ok = rows.array.ndim() == (wanted_columns ? 2 : 1);
  if (shape_ok && wanted_columns) {
    shape_ok = false;
    for (std::size_t c : columns) shape_ok |= std::size_t(rows.array.shape(1)) == c;
  }
  if (!shape_ok) {
    std::string expected = wanted_columns ? "(count, " : "(count,)";
    if (wanted_columns) {
      for (auto c = columns.begin(); c != columns.end(); ++c)
        expected += (c == columns.begin() ? "" : " or ") + std::to_string(*c);
      expected += ")";
    }
    invalid_argument(name + ": expected shape " + expected + ", got " + shape_text(rows.array));
  }
  rows.present = true;
  rows.data = static_cast<const char*>(rows.array.data());
  rows.count = std::size_t(rows.array.shape(0));
  rows.row_stride = rows.array.strides(0);
  rows.columns = wanted_columns ? std::size_t(rows.array.shape(1)) : 1;
  rows.column_stride = wanted_columns ? rows.array.strides(1) : 0;
  return rows;
}

void check_finite(const Rows<float>& rows, const std::string& name) {
  for (std::size_t r = 0; r < rows.count; ++r)
    for (std::size_t c = 0; c < rows.columns; ++c)
      if (!std::isfinite(rows.at(r, c)))
        invalid_argument(name + ": row " + std::to_string(r) + " is not finite (NaN or infinity)");
}

// Every index below `limit`, or kNoAttribute where `optional`.
void check_indices(const Rows<uint32_t>& rows, std::size_t limit, bool optional,
                   const std::string& name, const std::string& of) {
  for (std::size_t r = 0; r < rows.count; ++r)
    for (std::size_t c = 0; c < rows.columns; ++c) {
      const uint32_t index = rows.at(r, c);
      if (index < limit || (optional && index == pm::kNoAttribute)) continue;
      invalid_argument(name + ": row " + std::to_string(r) + " refers to " + of + " " +
                       std::to_string(index) + " of " + std::to_string(limit));
    }
}

std::vector<std::string> strings_of(const py::list& list, const std::string& name) {
  std::vector<std::string> strings;
  for (const py::handle item : list) {
    if (!py::isinstance<py::str>(item)) invalid_argument(name + ": expected a list of str");
    strings.push_back(item.cast<std::string>());
  }
  return strings;
}

// The checked arrays of a Python mesh.
struct Checked {
  Rows<float> positions, uvs, normals, colors;
  Rows<uint32_t> faces, uv_indices, normal_indices, face_materials;
  std::vector<std::string> material_names, material_libraries;
};

Checked check(const Mesh& mesh, const std::string& what) {
  const std::string prefix = what.empty() ? "" : what + ": ";
  Checked c;
  if (mesh.positions.is_none() || mesh.faces.is_none())
    invalid_argument(prefix + "a mesh needs positions and faces");
  c.positions = rows_of<float>(mesh.positions, prefix + "positions", {3});
  c.faces = rows_of<uint32_t>(mesh.faces, prefix + "faces", {3});
  c.uvs = rows_of<float>(mesh.uvs, prefix + "uvs", {2});
  c.uv_indices = rows_of<uint32_t>(mesh.uv_indices, prefix + "uv_indices", {3});
  c.normals = rows_of<float>(mesh.normals, prefix + "normals", {3});
  c.normal_indices = rows_of<uint32_t>(mesh.normal_indices, prefix + "normal_indices", {3});
  c.colors = rows_of<float>(mesh.colors, prefix + "colors", {3, 4});
  c.face_materials = rows_of<uint32_t>(mesh.face_materials, prefix + "face_materials", {0});
  c.material_names = strings_of(mesh.material_names, prefix + "material_names");
  c.material_libraries = strings_of(mesh.material_libraries, prefix + "material_libraries");

  const std::size_t vertices = c.positions.count, faces = c.faces.count;
  const auto same_rows = [&](const auto& rows, std::size_t count, const char* name, const char* of) {
    if (rows.present && rows.count != count)
      invalid_argument(prefix + name + ": " + std::to_string(rows.count) + " rows for " +
                       std::to_string(count) + " " + of);
  };
  const auto paired = [&](bool values, bool indices, const char* a, const char* b) {
    if (values != indices) invalid_argument(prefix + a + " and " + b + " go together");
  };
  paired(c.uvs.present, c.uv_indices.present, "uvs", "uv_indices");
  paired(c.normals.present, c.normal_indices.present, "normals", "normal_indices");
  same_rows(c.uv_indices, faces, "uv_indices", "faces");
  same_rows(c.normal_indices, faces, "normal_indices", "faces");
  same_rows(c.colors, vertices, "colors", "vertices");
  same_rows(c.face_materials, faces, "face_materials", "faces");

  check_finite(c.positions, prefix + "positions");
  check_finite(c.uvs, prefix + "uvs");
  check_finite(c.normals, prefix + "normals");
  check_finite(c.colors, prefix + "colors");
  check_indices(c.faces, vertices, false, prefix + "faces", "vertex");
  check_indices(c.uv_indices, c.uvs.count, true, prefix + "uv_indices", "texture coordinate");
  check_indices(c.normal_indices, c.normals.count, true, prefix + "normal_indices", "normal");
  check_indices(c.face_materials, c.material_names.size(), true, prefix + "face_materials",
                "material");
  return c;
}

}  // namespace

Mesh wrap_mesh(pm::Mesh&& library) {
  auto held = std::make_shared<const pm::Mesh>(std::move(library));
  const pm::Mesh& m = *held;
  // The capsule owns a reference to the mesh; every view below keeps the capsule.
  py::capsule owner(new std::shared_ptr<const pm::Mesh>(held),
                    [](void* p) { delete static_cast<std::shared_ptr<const pm::Mesh>*>(p); });
  Mesh mesh;
  mesh.positions = view(m.positions.data(), m.vertex_count(), 3, owner, true);
  mesh.faces = view(m.triangles.data(), m.face_count(), 3, owner, true);
  // Absent attributes stay None (no array made for them).
  if (m.has_uvs()) {
    mesh.uvs = view(m.uvs.data(), m.uv_count(), 2, owner, true);
    mesh.uv_indices = view(m.uv_indices.data(), m.face_count(), 3, owner, true);
  }
  if (m.has_normals()) {
    mesh.normals = view(m.normals.data(), m.normal_count(), 3, owner, true);
    mesh.normal_indices = view(m.normal_indices.data(), m.face_count(), 3, owner, true);
  }
  if (m.has_colors()) mesh.colors = view(m.colors.data(), m.vertex_count(), m.color_components, owner, true);
  if (m.has_materials()) mesh.face_materials = view(m.face_materials.data(), m.face_count(), 0, owner, true);
  for (const std::string& name : m.material_names) mesh.material_names.append(name);
  for (const std::string& name : m.material_libraries) mesh.material_libraries.append(name);
  mesh.source = std::move(held);
  mesh.source_arrays = array_pointers(mesh);
  return mesh;
}

const pm::Mesh& library_mesh(const Mesh& mesh, const char* what, pm::Mesh& storage) {
  const Checked c = check(mesh, what);
  if (mesh.source && mesh.source_arrays == array_pointers(mesh) &&
      c.material_names == mesh.source->material_names &&
      c.material_libraries == mesh.source->material_libraries)
    return *mesh.source;
  storage = pm::Mesh();
  c.positions.append_to(storage.positions);
  c.faces.append_to(storage.triangles);
  c.uvs.append_to(storage.uvs);
  c.uv_indices.append_to(storage.uv_indices);
  c.normals.append_to(storage.normals);
  c.normal_indices.append_to(storage.normal_indices);
  storage.color_components = c.colors.present ? uint32_t(c.colors.columns) : 0;
  c.colors.append_to(storage.colors);
  c.face_materials.append_to(storage.face_materials);
  storage.material_names = c.material_names;
  storage.material_libraries = c.material_libraries;
  return storage;
}

namespace {

// rows as a library view: the numpy array's own memory when its values are packed in rows,
// else a packed copy in `storage`.
template <class T>
pm::RowsView<T> rows_view(const Rows<T>& rows, std::vector<T>& storage, std::size_t& copied) {
  if (!rows.present || rows.count == 0) return {};
  const std::size_t row = rows.columns * sizeof(T);
  const bool packed_columns = rows.columns <= 1 || rows.column_stride == py::ssize_t(sizeof(T));
  if (packed_columns && (rows.count == 1 || rows.row_stride >= py::ssize_t(row)))
    return {reinterpret_cast<const T*>(rows.data), rows.count,
            rows.count == 1 ? 0 : std::size_t(rows.row_stride)};
  rows.append_to(storage);
  ++copied;
  return {storage.data(), rows.count, 0};
}

}  // namespace

void library_input(const Mesh& mesh, const char* what, LibraryInput& out) {
  const Checked c = check(mesh, what);
  out.faces = c.faces.count;
  if (mesh.source && mesh.source_arrays == array_pointers(mesh) &&
      c.material_names == mesh.source->material_names &&
      c.material_libraries == mesh.source->material_libraries) {
    out.mesh = mesh.source.get();
    return;
  }
  std::size_t& copied = out.copied_arrays;
  pm::MeshView& v = out.view;
  v.positions = rows_view(c.positions, out.float_storage[0], copied);
  v.uvs = rows_view(c.uvs, out.float_storage[1], copied);
  v.normals = rows_view(c.normals, out.float_storage[2], copied);
  v.colors = rows_view(c.colors, out.float_storage[3], copied);
  v.color_components = c.colors.present ? uint32_t(c.colors.columns) : 0;
  v.triangles = rows_view(c.faces, out.index_storage[0], copied);
  v.uv_indices = rows_view(c.uv_indices, out.index_storage[1], copied);
  v.normal_indices = rows_view(c.normal_indices, out.index_storage[2], copied);
  v.face_materials = rows_view(c.face_materials, out.index_storage[3], copied);
  out.material_names = c.material_names;
  out.material_libraries = c.material_libraries;
  v.material_names = &out.material_names;
  v.material_libraries = &out.material_libraries;
}

void register_mesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", R"(A triangle mesh as plain numpy arrays.

positions (n, 3) float32 and faces (m, 3) uint32 (counter-clockwise) are required. Optional,
each None when absent: uvs (k, 2) float32 with uv_indices (m, 3) uint32 (a texture coordinate
per corner, as OBJ's vt); normals (j, 3) float32 with normal_indices (m, 3) uint32 (as OBJ's
vn); colors (n, 3 or 4) float32, one per vertex; face_materials (m,) uint32 into
material_names (list of str, OBJ usemtl); material_libraries (list of str, OBJ mtllib).
A corner or face without the attribute holds NO_ATTRIBUTE.

Meshes the library returns are views of its own memory (no copy); the arrays stay valid as
long as any of them is referenced. The constructor checks dtypes, shapes, finite values and
index ranges, and raises pmesh.Error (code 'invalid-argument') naming the first problem.)")
      .def(py::init([](py::object positions, py::object faces, py::object uvs,
                       py::object uv_indices, py::object normals, py::object normal_indices,
                       py::object colors, py::object face_materials, py::list material_names,
                       py::list material_libraries) {
             Mesh mesh;
             mesh.positions = std::move(positions);
             mesh.faces = std::move(faces);
             mesh.uvs = std::move(uvs);
             mesh.uv_indices = std::move(uv_indices);
             mesh.normals = std::move(normals);
             mesh.normal_indices = std::move(normal_indices);
             mesh.colors = std::move(colors);
             mesh.face_materials = std::move(face_materials);
             mesh.material_names = std::move(material_names);
             mesh.material_libraries = std::move(material_libraries);
             check(mesh, "");
             return mesh;
           }),
           py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("uvs") = py::none(),
           py::arg("uv_indices") = py::none(), py::arg("normals") = py::none(),
           py::arg("normal_indices") = py::none(), py::arg("colors") = py::none(),
           py::arg("face_materials") = py::none(), py::arg("material_names") = py::list(),
           py::arg("material_libraries") = py::list())
      .def_readwrite("positions", &Mesh::positions, "(n, 3) float32: x, y, z per vertex")
      .def_readwrite("faces", &Mesh::faces, "(m, 3) uint32: three vertex indices per face")
      .def_readwrite("uvs", &Mesh::uvs, "(k, 2) float32 texture coordinates, or None")
      .def_readwrite("uv_indices", &Mesh::uv_indices, "(m, 3) uint32: each corner's uv, or None")
      .def_readwrite("normals", &Mesh::normals, "(j, 3) float32 normals (as stored), or None")
      .def_readwrite("normal_indices", &Mesh::normal_indices,
                     "(m, 3) uint32: each corner's normal, or None")
      .def_readwrite("colors", &Mesh::colors, "(n, 3 or 4) float32 per vertex, or None")
      .def_readwrite("face_materials", &Mesh::face_materials,
                     "(m,) uint32: each face's index into material_names, or None")
      .def_readwrite("material_names", &Mesh::material_names, "list of str (OBJ usemtl)")
      .def_readwrite("material_libraries", &Mesh::material_libraries, "list of str (OBJ mtllib)")
      .def("check", [](const Mesh& mesh) { check(mesh, ""); },
           "Raises pmesh.Error (invalid-argument) if the arrays do not form a valid mesh.")
      .def("__repr__", [](const Mesh& mesh) {
        std::string text = "pmesh.Mesh(";
        const auto rows = [](const py::object& a) {
          return py::isinstance<py::array>(a) ? std::to_string(py::reinterpret_borrow<py::array>(a).shape(0))
                                              : std::string("?");
        };
        text += rows(mesh.positions) + " vertices, " + rows(mesh.faces) + " faces";
        if (!mesh.uvs.is_none()) text += ", uvs";
        if (!mesh.normals.is_none()) text += ", normals";
        if (!mesh.colors.is_none()) text += ", colors";
        if (!mesh.face_materials.is_none())
          text += ", " + std::to_string(mesh.material_names.size()) + " materials";
        return text + ")";
      });
}

}  // namespace pmesh

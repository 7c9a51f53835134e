#pragma once
// Structure scans run on a surface file's bytes before CGAL's reader sees
// them (surface_reader.cpp). CGAL's readers trust the numbers a file gives
// about itself: OFF resizes its arrays to the header's counts, PLY resizes a
// face's list to the count it reads (also past the end of the data, from an
// uninitialised buffer), a PLY property declared before any element indexes
// an empty vector, a PLY vertex whose x is an integer dereferences a null
// pointer, and an element with items but no properties loops without end.
// Each scan walks the structure those readers will walk, without converting
// values, and fails (naming the file and the line or byte) where the file
// announces more than it holds or has a shape the reader would misread; what
// passes makes every count CGAL reads bounded by the bytes that hold it.
#include <string>
#include <string_view>

namespace softcut::mesh::io {

// Binary STL: the 80-byte header and the triangle count must fit, and the
// count's 50-byte records must be there. (ASCII STL has no counts.)
void scan_stl(const std::string& source, std::string_view bytes);

// ASCII OFF (plain "OFF": no colours, normals, homogeneous or n-dimensional
// variants, no BINARY): the counts, one line per vertex with >= 3 numbers,
// one line per face "n i1 .. in" with indices below the vertex count.
void scan_off(const std::string& source, std::string_view bytes);

// PLY (ascii, binary_little_endian, binary_big_endian): a header CGAL's
// reader understands (known types, properties after their element, x y z as
// float/double scalars, faces with an int/uint index list), and a body that
// holds every element, list counts included.
void scan_ply(const std::string& source, std::string_view bytes);

}  // namespace softcut::mesh::io

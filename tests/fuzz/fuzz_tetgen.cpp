// libFuzzer target: the TetGen reader (.node + .ele). The input is the .node
// text, one NUL byte, then the .ele text (no NUL: empty .ele); both go to
// scratch files because read_tetgen takes paths.
#include <cstring>

#include "mesh_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softcut;
  const std::string_view all = fuzz::as_text(data, size);
  const std::size_t cut = all.find('\0');
  const auto node = fuzz::put_file("fuzz.node", all.substr(0, cut));
  const auto ele = fuzz::put_file("fuzz.ele", cut == all.npos ? std::string_view() : all.substr(cut + 1));
  fuzz::expect_clean([&] {
    Diagnostics diag;
    mesh::TetMesh m = mesh::io::read_tetgen(node, ele, diag);
    if (m.num_tets() == 0) return;
    mesh::validate(m, "fuzz.node", diag);
  });
  return 0;
}

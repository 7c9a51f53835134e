#pragma once
// Base64 (RFC 4648, standard alphabet) for VTK XML binary data arrays.
#include <optional>
#include <string>
#include <string_view>

namespace softcut::mesh::io {

std::string base64_encode(std::string_view bytes);

// Decodes text that may be several padded base64 streams written one after
// the other (VTK encodes a data array's header and its data separately).
// Whitespace is ignored. Returns nullopt, with the offending character offset
// in `bad_at`, on a character outside the alphabet or a truncated group.
std::optional<std::string> base64_decode(std::string_view text, std::size_t* bad_at = nullptr);

}  // namespace softcut::mesh::io

// The first bytes of an untrusted file, for a message that says what the file is not:
// printable ASCII as it is, anything else as \xNN, at most 8 bytes, quoted, so a message
// never echoes much of a client's data.
#pragma once

#include <string>
#include <string_view>

namespace spheremap {

std::string shown_prefix(std::string_view bytes);

}  // namespace spheremap

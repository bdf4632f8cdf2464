// RFC 4122 UUIDs for the record: random ones (v4) for attempts and registrations, name-based
// ones (v5, SHA-1) for xAPI statement ids, so exporting the same attempt twice gives the same
// statement ids and a learning record store can drop the duplicates.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace acdr {

/// A random (version 4) UUID in lower-case 8-4-4-4-12 form.
std::string make_uuid_v4();

/// A name-based (version 5, SHA-1) UUID of `name` in the namespace `namespace_uuid` (itself a
/// UUID in text form). nullopt when `namespace_uuid` is not a UUID.
std::optional<std::string> make_uuid_v5(std::string_view namespace_uuid, std::string_view name);

/// True for "xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx" with hex digits (either case).
bool is_uuid(std::string_view text);

/// SHA-1 digest (FIPS 180-4) of `data`, as 40 lower-case hex digits. Used for v5 UUIDs only;
/// SHA-1 is not used for anything that needs collision resistance.
std::string sha1_hex(std::string_view data);

}  // namespace acdr

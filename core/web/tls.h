// The web page's certificate: the user's own (cert and key PEM files), or one Marvin makes
// on first start and keeps in its state folder.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace marvin::web {

// Writes a self-signed certificate (EC P-256, valid 10 years, CN "Marvin") for the
// `names` ("localhost", "127.0.0.1", "marvin.local": IP addresses become IP entries, the
// rest DNS entries) to `cert`, and its private key to `key` (mode 0600). Throws naming the
// file that cannot be written.
void make_self_signed_certificate(const std::filesystem::path& cert,
                                  const std::filesystem::path& key,
                                  const std::vector<std::string>& names);

}  // namespace marvin::web

// minisign-compatible keys and signatures (https://jedisct1.github.io/minisign/), verified
// and made with libsodium.
//
// Supported:
//  - public keys: the two-line `.pub` file or the bare base64 line (`minisign -P`).
//  - signatures: algorithm "ED" (Ed25519 over the BLAKE2b-512 hash of the file, minisign's
//    default since 0.8) and legacy "Ed" (Ed25519 over the file itself), the key id, the
//    trusted comment and its global signature (Ed25519 over signature || trusted comment).
//  - secret keys: unencrypted keys (`minisign -G -W`), and scrypt-encrypted keys (the
//    minisign default) when a password is given. We always sign with "ED".
//
// All functions throw std::runtime_error whose message starts with `origin` (usually the
// file name) and says which field is wrong.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::store {

using KeyId = std::array<std::uint8_t, 8>;

struct PublicKey {
  KeyId key_id{};
  std::array<std::uint8_t, 32> key{};
  // The key id as minisign prints it: 16 upper-case hex digits, little-endian number.
  std::string id_text() const;
  // The base64 line of the `.pub` file (what `minisign -P` takes).
  std::string base64() const;
};

struct SecretKey {
  KeyId key_id{};
  std::array<std::uint8_t, 64> key{};  // libsodium Ed25519 secret key (seed || public key)
  PublicKey public_key() const;
};

struct Signature {
  bool prehashed = true;  // "ED" (BLAKE2b-512 prehash) or legacy "Ed"
  KeyId key_id{};
  std::array<std::uint8_t, 64> signature{};
  std::string untrusted_comment;
  std::string trusted_comment;
  std::array<std::uint8_t, 64> global_signature{};
};

// Parses a `.pub` file's content or a bare base64 key.
PublicKey parse_public_key(std::string_view text, const std::string& origin);
PublicKey load_public_key(const std::filesystem::path& path);
// The `.pub` file content minisign writes.
std::string format_public_key(const PublicKey& key);

// Parses a secret key file. Encrypted keys need `password`; without one the message says
// so. Checks the key's checksum, so a wrong password is reported as such.
SecretKey parse_secret_key(std::string_view text, const std::string& origin,
                           const std::optional<std::string>& password = std::nullopt);
SecretKey load_secret_key(const std::filesystem::path& path,
                          const std::optional<std::string>& password = std::nullopt);
// An unencrypted secret key file, as `minisign -G -W` writes it.
std::string format_secret_key(const SecretKey& key);

// A fresh random key pair (tests, benchmarks, tools).
SecretKey generate_secret_key();

Signature parse_signature(std::string_view text, const std::string& origin);
std::string format_signature(const Signature& sig);

// Signs `message` ("ED" algorithm) and returns the `.minisig` file content. Comments must
// be one line.
std::string sign_message(std::span<const std::uint8_t> message, const SecretKey& key,
                         const std::string& trusted_comment,
                         const std::string& untrusted_comment = "signature from marvin");

// Checks `sig` over `message` against `trusted` keys: the key id must name one of them,
// the signature and the global signature (over the trusted comment) must verify. Returns
// the verified trusted comment. Throws naming `origin` and the reason: unknown key id
// (untrusted signer), bad signature, or tampered trusted comment.
std::string verify_message(std::span<const std::uint8_t> message, const Signature& sig,
                           const std::vector<PublicKey>& trusted, const std::string& origin);

}  // namespace marvin::store

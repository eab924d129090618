#include "store/minisign.h"

#include <sodium.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "store/util.h"

namespace marvin::store {
namespace {

constexpr std::size_t kSaltBytes = 32;
constexpr std::size_t kKeynumBytes = 8 + 64 + 32;  // key id, secret key, checksum

[[noreturn]] void fail(const std::string& origin, const std::string& what) {
  throw std::runtime_error(origin + ": " + what);
}

std::string trim_line(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return std::string(s);
}

std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.emplace_back(line);
    start = end + 1;
  }
  return lines;
}

Bytes from_base64(const std::string& b64, const std::string& origin, const std::string& field) {
  init_sodium();
  Bytes out(b64.size());
  std::size_t len = 0;
  const char* end = nullptr;
  if (sodium_base642bin(out.data(), out.size(), b64.data(), b64.size(), nullptr, &len, &end,
                        sodium_base64_VARIANT_ORIGINAL) != 0 ||
      end != b64.data() + b64.size()) {
    fail(origin, field + " is not valid base64");
  }
  out.resize(len);
  return out;
}

std::string to_base64(std::span<const std::uint8_t> bin) {
  init_sodium();
  std::string out(sodium_base64_ENCODED_LEN(bin.size(), sodium_base64_VARIANT_ORIGINAL), '\0');
  sodium_bin2base64(out.data(), out.size(), bin.data(), bin.size(), sodium_base64_VARIANT_ORIGINAL);
  out.resize(std::strlen(out.c_str()));
  return out;
}

std::string key_id_text(const KeyId& id) {
  std::array<std::uint8_t, 8> be{};
  std::reverse_copy(id.begin(), id.end(), be.begin());
  std::string hex = to_hex(be);
  std::transform(hex.begin(), hex.end(), hex.begin(),
                 [](char c) { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); });
  return hex;
}

std::uint64_t le64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

std::array<std::uint8_t, 32> secret_key_checksum(const std::uint8_t* alg, const SecretKey& k) {
  std::array<std::uint8_t, 32> chk{};
  crypto_generichash_state st;
  crypto_generichash_init(&st, nullptr, 0, chk.size());
  crypto_generichash_update(&st, alg, 2);
  crypto_generichash_update(&st, k.key_id.data(), k.key_id.size());
  crypto_generichash_update(&st, k.key.data(), k.key.size());
  crypto_generichash_final(&st, chk.data(), chk.size());
  return chk;
}

std::array<std::uint8_t, 64> blake2b512(std::span<const std::uint8_t> message) {
  std::array<std::uint8_t, 64> h{};
  crypto_generichash(h.data(), h.size(), message.data(), message.size(), nullptr, 0);
  return h;
}

void check_one_line(const std::string& comment, const char* what) {
  if (comment.find_first_of("\r\n") != std::string::npos) {
    throw std::runtime_error(std::string(what) + " must be a single line");
  }
}

}  // namespace

std::string PublicKey::id_text() const { return key_id_text(key_id); }

std::string PublicKey::base64() const {
  Bytes bin{'E', 'd'};
  bin.insert(bin.end(), key_id.begin(), key_id.end());
  bin.insert(bin.end(), key.begin(), key.end());
  return to_base64(bin);
}

PublicKey SecretKey::public_key() const {
  PublicKey pk;
  pk.key_id = key_id;
  std::copy(key.begin() + 32, key.end(), pk.key.begin());
  return pk;
}

PublicKey parse_public_key(std::string_view text, const std::string& origin) {
  std::string line;
  for (const std::string& raw : split_lines(text)) {
    std::string l = trim_line(raw);
    if (l.empty() || l.rfind("untrusted comment:", 0) == 0) continue;
    line = l;
    break;
  }
  if (line.empty()) fail(origin, "no public key line found");
  Bytes bin = from_base64(line, origin, "public key");
  if (bin.size() != 42) {
    fail(origin, "public key is " + std::to_string(bin.size()) + " bytes, expected 42");
  }
  if (bin[0] != 'E' || bin[1] != 'd') fail(origin, "public key algorithm is not Ed25519 (\"Ed\")");
  PublicKey pk;
  std::copy(bin.begin() + 2, bin.begin() + 10, pk.key_id.begin());
  std::copy(bin.begin() + 10, bin.end(), pk.key.begin());
  return pk;
}

PublicKey load_public_key(const std::filesystem::path& path) {
  return parse_public_key(read_text_file(path, 64 * 1024), path.string());
}

std::string format_public_key(const PublicKey& key) {
  return "untrusted comment: minisign public key " + key.id_text() + "\n" + key.base64() + "\n";
}

SecretKey parse_secret_key(std::string_view text, const std::string& origin,
                           const std::optional<std::string>& password) {
  init_sodium();
  std::vector<std::string> lines = split_lines(text);
  if (lines.size() < 2 || lines[0].rfind("untrusted comment:", 0) != 0) {
    fail(origin, "not a minisign secret key (expected an untrusted comment line and a key line)");
  }
  Bytes bin = from_base64(trim_line(lines[1]), origin, "secret key");
  constexpr std::size_t kExpected = 2 + 2 + 2 + kSaltBytes + 8 + 8 + kKeynumBytes;
  if (bin.size() != kExpected) {
    fail(origin, "secret key is " + std::to_string(bin.size()) + " bytes, expected " +
                     std::to_string(kExpected));
  }
  const std::uint8_t* sig_alg = bin.data();
  const std::uint8_t* kdf_alg = bin.data() + 2;
  const std::uint8_t* chk_alg = bin.data() + 4;
  const std::uint8_t* salt = bin.data() + 6;
  std::uint64_t opslimit = le64(bin.data() + 6 + kSaltBytes);
  std::uint64_t memlimit = le64(bin.data() + 6 + kSaltBytes + 8);
  std::uint8_t* keynum = bin.data() + 6 + kSaltBytes + 16;
  if (sig_alg[0] != 'E' || sig_alg[1] != 'd') fail(origin, "secret key algorithm is not \"Ed\"");
  if (chk_alg[0] != 'B' || chk_alg[1] != '2') fail(origin, "secret key checksum algorithm is not \"B2\"");
  const bool encrypted = kdf_alg[0] == 'S' && kdf_alg[1] == 'c';
  if (!encrypted && !(kdf_alg[0] == 0 && kdf_alg[1] == 0)) {
    fail(origin, "unknown key derivation algorithm (expected scrypt \"Sc\" or none)");
  }
  if (encrypted) {
    if (!password) {
      fail(origin, "secret key is encrypted with a password; give the password "
                   "(MARVIN_SIGN_PASSWORD) or use a key made with `minisign -G -W`");
    }
    if (memlimit > (std::uint64_t{4} << 30)) fail(origin, "secret key's scrypt memory limit is too large");
    std::array<std::uint8_t, kKeynumBytes> stream{};
    if (crypto_pwhash_scryptsalsa208sha256(stream.data(), stream.size(), password->data(),
                                           password->size(), salt, opslimit,
                                           static_cast<std::size_t>(memlimit)) != 0) {
      fail(origin, "scrypt key derivation failed (out of memory?)");
    }
    for (std::size_t i = 0; i < kKeynumBytes; ++i) keynum[i] ^= stream[i];
    sodium_memzero(stream.data(), stream.size());
  }
  SecretKey sk;
  std::copy(keynum, keynum + 8, sk.key_id.begin());
  std::copy(keynum + 8, keynum + 72, sk.key.begin());
  // minisign 0.11 leaves the checksum all zero in unencrypted (-W) keys; check it when it
  // is set, and always check that the public half matches the seed.
  std::array<std::uint8_t, 32> chk = secret_key_checksum(sig_alg, sk);
  const bool zero_chk = !encrypted && sodium_is_zero(keynum + 72, 32) == 1;
  if (!zero_chk && sodium_memcmp(chk.data(), keynum + 72, 32) != 0) {
    fail(origin, encrypted ? "wrong password for the secret key (checksum mismatch)"
                           : "secret key checksum mismatch (corrupted key file)");
  }
  std::array<std::uint8_t, 32> derived_pk{};
  std::array<std::uint8_t, 64> derived_sk{};
  crypto_sign_seed_keypair(derived_pk.data(), derived_sk.data(), sk.key.data());
  const bool consistent = sodium_memcmp(derived_pk.data(), sk.key.data() + 32, 32) == 0;
  sodium_memzero(derived_sk.data(), derived_sk.size());
  if (!consistent) {
    fail(origin, encrypted ? "wrong password for the secret key (key does not match its public half)"
                           : "secret key checksum mismatch (corrupted key file: key does not match its public half)");
  }
  sodium_memzero(bin.data(), bin.size());
  return sk;
}

SecretKey load_secret_key(const std::filesystem::path& path,
                          const std::optional<std::string>& password) {
  return parse_secret_key(read_text_file(path, 64 * 1024), path.string(), password);
}

std::string format_secret_key(const SecretKey& key) {
  Bytes bin{'E', 'd', 0, 0, 'B', '2'};
  bin.resize(bin.size() + kSaltBytes + 16, 0);
  bin.insert(bin.end(), key.key_id.begin(), key.key_id.end());
  bin.insert(bin.end(), key.key.begin(), key.key.end());
  const std::uint8_t alg[2] = {'E', 'd'};
  std::array<std::uint8_t, 32> chk = secret_key_checksum(alg, key);
  bin.insert(bin.end(), chk.begin(), chk.end());
  return "untrusted comment: minisign secret key (unencrypted)\n" + to_base64(bin) + "\n";
}

SecretKey generate_secret_key() {
  init_sodium();
  SecretKey sk;
  std::array<std::uint8_t, 32> pk{};
  crypto_sign_keypair(pk.data(), sk.key.data());
  randombytes_buf(sk.key_id.data(), sk.key_id.size());
  return sk;
}

Signature parse_signature(std::string_view text, const std::string& origin) {
  std::vector<std::string> lines = split_lines(text);
  while (!lines.empty() && trim_line(lines.back()).empty()) lines.pop_back();
  if (lines.size() != 4) {
    fail(origin, "malformed signature: expected 4 lines (untrusted comment, signature, "
                 "trusted comment, global signature), found " + std::to_string(lines.size()));
  }
  Signature sig;
  const std::string kUntrusted = "untrusted comment: ";
  const std::string kTrusted = "trusted comment: ";
  if (lines[0].rfind(kUntrusted, 0) != 0) fail(origin, "malformed signature: line 1 is not an untrusted comment");
  sig.untrusted_comment = lines[0].substr(kUntrusted.size());
  Bytes bin = from_base64(trim_line(lines[1]), origin, "signature");
  if (bin.size() != 74) {
    fail(origin, "malformed signature: signature is " + std::to_string(bin.size()) + " bytes, expected 74");
  }
  if (bin[0] == 'E' && bin[1] == 'D') {
    sig.prehashed = true;
  } else if (bin[0] == 'E' && bin[1] == 'd') {
    sig.prehashed = false;
  } else {
    fail(origin, "malformed signature: unknown algorithm (expected \"ED\" or \"Ed\")");
  }
  std::copy(bin.begin() + 2, bin.begin() + 10, sig.key_id.begin());
  std::copy(bin.begin() + 10, bin.end(), sig.signature.begin());
  if (lines[2].rfind(kTrusted, 0) != 0) fail(origin, "malformed signature: line 3 is not a trusted comment");
  sig.trusted_comment = lines[2].substr(kTrusted.size());
  Bytes global = from_base64(trim_line(lines[3]), origin, "global signature");
  if (global.size() != 64) {
    fail(origin, "malformed signature: global signature is " + std::to_string(global.size()) +
                     " bytes, expected 64");
  }
  std::copy(global.begin(), global.end(), sig.global_signature.begin());
  return sig;
}

std::string format_signature(const Signature& sig) {
  Bytes bin{'E', sig.prehashed ? std::uint8_t{'D'} : std::uint8_t{'d'}};
  bin.insert(bin.end(), sig.key_id.begin(), sig.key_id.end());
  bin.insert(bin.end(), sig.signature.begin(), sig.signature.end());
  return "untrusted comment: " + sig.untrusted_comment + "\n" + to_base64(bin) +
         "\ntrusted comment: " + sig.trusted_comment + "\n" + to_base64(sig.global_signature) + "\n";
}

std::string sign_message(std::span<const std::uint8_t> message, const SecretKey& key,
                         const std::string& trusted_comment, const std::string& untrusted_comment) {
  init_sodium();
  check_one_line(trusted_comment, "trusted comment");
  check_one_line(untrusted_comment, "untrusted comment");
  Signature sig;
  sig.prehashed = true;
  sig.key_id = key.key_id;
  sig.untrusted_comment = untrusted_comment;
  sig.trusted_comment = trusted_comment;
  std::array<std::uint8_t, 64> h = blake2b512(message);
  crypto_sign_detached(sig.signature.data(), nullptr, h.data(), h.size(), key.key.data());
  Bytes global(sig.signature.begin(), sig.signature.end());
  global.insert(global.end(), trusted_comment.begin(), trusted_comment.end());
  crypto_sign_detached(sig.global_signature.data(), nullptr, global.data(), global.size(),
                       key.key.data());
  return format_signature(sig);
}

std::string verify_message(std::span<const std::uint8_t> message, const Signature& sig,
                           const std::vector<PublicKey>& trusted, const std::string& origin) {
  init_sodium();
  const PublicKey* key = nullptr;
  for (const PublicKey& k : trusted) {
    if (k.key_id == sig.key_id) key = &k;
  }
  if (key == nullptr) {
    std::string known;
    for (const PublicKey& k : trusted) known += (known.empty() ? "" : ", ") + k.id_text();
    fail(origin, "signed by untrusted key " + key_id_text(sig.key_id) + " (trusted: " +
                     (known.empty() ? "none" : known) + ")");
  }
  int rc;
  if (sig.prehashed) {
    std::array<std::uint8_t, 64> h = blake2b512(message);
    rc = crypto_sign_verify_detached(sig.signature.data(), h.data(), h.size(), key->key.data());
  } else {
    rc = crypto_sign_verify_detached(sig.signature.data(), message.data(), message.size(),
                                     key->key.data());
  }
  if (rc != 0) fail(origin, "signature verification failed for key " + key->id_text() + " (content changed or wrong key)");
  Bytes global(sig.signature.begin(), sig.signature.end());
  global.insert(global.end(), sig.trusted_comment.begin(), sig.trusted_comment.end());
  if (crypto_sign_verify_detached(sig.global_signature.data(), global.data(), global.size(),
                                  key->key.data()) != 0) {
    fail(origin, "trusted comment signature verification failed (trusted comment tampered)");
  }
  return sig.trusted_comment;
}

}  // namespace marvin::store

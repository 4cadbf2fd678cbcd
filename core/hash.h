#pragma once
// Non-cryptographic 64-bit hashes: every hash Sylva stores or compares lives here. Values are part of
// the file formats (golden/*.toml determinism_hash and scene_hash, golden/geometry/*.json mesh_hash,
// checkpoint keys), so none of these functions may change a bit. Byte order is the machine's
// (little-endian on every supported platform).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mix with full avalanche.
inline constexpr uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Order-dependent hash of a seed and any number of integer ids (random-stream seeds, docs/design.md
// §4, and combined content hashes).
template <typename... Ids>
inline constexpr uint64_t hash_ids(uint64_t seed, Ids... ids) {
  uint64_t h = mix64(seed);
  ((h = mix64(h ^ static_cast<uint64_t>(ids))), ...);
  return h;
}

// What the byte hashers below share: a 64-bit state fed bytes by the hasher's add(data, bytes),
// and add_vector for arrays of plain values (their bytes as stored, padding included).
template <typename Hasher>
class ByteHasher64 {
 public:
  template <typename T>
  Hasher& add_vector(const std::vector<T>& v) {
    return static_cast<Hasher&>(*this).add(v.data(), v.size() * sizeof(T));
  }
  uint64_t value() const { return h_; }

 protected:
  explicit ByteHasher64(uint64_t initial) : h_(initial) {}
  uint64_t h_;
};

// FNV-1a, 64-bit (Fowler, Noll & Vo; IETF draft-eastlake-fnv), fed a byte stream in pieces: hashing
// "ab" in one call or as "a" then "b" gives the same value. Used for image and scene-text hashes.
class Fnv1a64 : public ByteHasher64<Fnv1a64> {
 public:
  static constexpr uint64_t kOffsetBasis = 0xcbf29ce484222325ull;
  static constexpr uint64_t kPrime = 0x100000001b3ull;

  Fnv1a64() : ByteHasher64(kOffsetBasis) {}
  Fnv1a64& add(const void* data, size_t bytes);
  Fnv1a64& add(std::string_view text) { return add(text.data(), text.size()); }
};

// FNV-1a 64 of a string's bytes.
uint64_t fnv1a64(std::string_view text);

// Word hash of binary arrays: each add() folds the bytes in as 8-byte words (h = mix64(h ^ word)),
// then one closing word: the byte count with the 0-7 remaining bytes shifted in after it, so arrays
// of different lengths differ even when their bytes agree. Eight bytes per step instead of FNV-1a's
// one; used for tree mesh hashes (geometry/trees/tree_stats.h).
class WordHash64 : public ByteHasher64<WordHash64> {
 public:
  static constexpr uint64_t kSeed = 0x5139a7eull;

  WordHash64() : ByteHasher64(kSeed) {}
  WordHash64& add(const void* data, size_t bytes);
};

// Sixteen lower-case hexadecimal digits, as hashes are stored in text files.
std::string hex64(uint64_t h);

}  // namespace sylva

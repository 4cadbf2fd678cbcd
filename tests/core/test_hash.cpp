// Hashes (core/hash.h): published test vectors, streaming equals one-shot, and the word hash's
// definition. Stored hashes (goldens) are checked end to end by tests/compare.

#include "core/hash.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace sylva {
namespace {

TEST(Hash, Fnv1a64PublishedVectors) {
  // Test vectors of the FNV reference (Landon Curt Noll, "FNV hash test vectors", 64-bit FNV-1a).
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ull);
}

TEST(Hash, Fnv1a64StreamsInAnyPieces) {
  const std::string text = "The quick brown fox jumps over the lazy dog";
  for (size_t cut = 0; cut <= text.size(); ++cut) {
    Fnv1a64 h;
    h.add(std::string_view(text).substr(0, cut)).add(std::string_view(text).substr(cut));
    EXPECT_EQ(h.value(), fnv1a64(text)) << cut;
  }
  // Binary data with zero bytes, through the vector overload.
  const std::vector<float> values{0.0f, 1.0f, -2.5f};
  std::string bytes(sizeof(float) * values.size(), '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());
  EXPECT_EQ(Fnv1a64().add_vector(values).value(), fnv1a64(bytes));
  EXPECT_NE(fnv1a64(bytes), fnv1a64(""));
}

TEST(Hash, Mix64IsSplitMix64) {
  // The first output of SplitMix64 seeded with 0 (Steele, Lea & Flood 2014; Vigna's splitmix64.c).
  EXPECT_EQ(mix64(0), 0xe220a8397b1dcdafull);
  EXPECT_NE(hash_ids(1, 2ull, 3ull), hash_ids(1, 3ull, 2ull));  // order matters
  EXPECT_EQ(hash_ids(7, 5ull), mix64(mix64(7) ^ 5));
}

TEST(Hash, WordHashFollowsItsDefinition) {
  // Three bytes: no full word, one closing word (byte count, then the bytes).
  const unsigned char three[3] = {1, 2, 3};
  EXPECT_EQ(WordHash64().add(three, 3).value(), mix64(WordHash64::kSeed ^ ((3ull << 24) | 0x010203ull)));
  // Eight bytes: one word, then the closing word is the count alone.
  const uint64_t word = 0x0123456789abcdefull;
  EXPECT_EQ(WordHash64().add(&word, 8).value(), mix64(mix64(WordHash64::kSeed ^ word) ^ 8));
  // The count separates arrays whose bytes agree: [] then [0] differs from [0] then [].
  const std::vector<uint8_t> empty, zero{0};
  EXPECT_NE(WordHash64().add_vector(empty).add_vector(zero).value(),
            WordHash64().add_vector(zero).add_vector(empty).value());
}

TEST(Hash, Hex64IsSixteenLowerCaseDigits) {
  EXPECT_EQ(hex64(0), "0000000000000000");
  EXPECT_EQ(hex64(0xABull), "00000000000000ab");
  EXPECT_EQ(hex64(0xcbf29ce484222325ull), "cbf29ce484222325");
}

}  // namespace
}  // namespace sylva

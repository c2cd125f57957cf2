#pragma once
// Deterministic mutation of file bytes for the fuzz tests: the same (seed, index) gives the same
// mutant on every platform (a splitmix64 stream, no std:: distributions). Four kinds, cycled by
// index: bit flips, a zeroed block, a truncation, a huge number written over a number (text
// files: a decimal token; binary files: 4 or 8 bytes set to all ones or INT_MAX).

#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

namespace taskmap::test {

/// Mutation kinds, in the order index % 4 picks them.
enum class Mutation { kBitFlips, kZeroedBlock, kTruncation, kHugeNumber };

/// Name of a kind, for reports.
inline const char* toString(Mutation m) {
  switch (m) {
    case Mutation::kBitFlips:
      return "bit_flips";
    case Mutation::kZeroedBlock:
      return "zeroed_block";
    case Mutation::kTruncation:
      return "truncation";
    case Mutation::kHugeNumber:
      return "huge_number";
  }
  return "?";
}

/// splitmix64: a tiny, portable, well-mixed stream.
class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform-enough integer in [0, n) (n > 0).
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }

 private:
  std::uint64_t state_;
};

/// Kind of mutant number index.
inline Mutation mutationOf(std::size_t index) {
  return static_cast<Mutation>(index % 4);
}

/// Mutant number index of original (not empty), from seed. first_byte: mutations start at or
/// after this offset (e.g. 512 to leave a map's seal intact and hit the HDF5 content).
inline std::string mutate(const std::string& original, std::uint64_t seed, std::size_t index,
                          std::size_t first_byte = 0) {
  SplitMix rng(seed * 1000003ULL + index);
  std::string b = original;
  const std::size_t lo = first_byte < b.size() ? first_byte : 0;
  const std::size_t span = b.size() - lo;
  switch (mutationOf(index)) {
    case Mutation::kBitFlips: {
      const std::size_t flips = 1 + rng.below(8);
      for (std::size_t i = 0; i < flips; ++i) {
        const std::size_t at = lo + rng.below(span);
        b[at] = static_cast<char>(b[at] ^ (1 << rng.below(8)));
      }
      break;
    }
    case Mutation::kZeroedBlock: {
      const std::size_t at = lo + rng.below(span);
      const std::size_t n = 1 + rng.below(256);
      for (std::size_t i = at; i < b.size() && i < at + n; ++i) b[i] = '\0';
      break;
    }
    case Mutation::kTruncation:
      b.resize(lo + rng.below(span));
      break;
    case Mutation::kHugeNumber: {
      // Text: replace a decimal token; binary (or no token found): overwrite 4 or 8 bytes.
      std::vector<std::size_t> starts;
      for (std::size_t i = lo; i < b.size(); ++i)
        if (std::isdigit(static_cast<unsigned char>(b[i])) &&
            (i == 0 || std::isspace(static_cast<unsigned char>(b[i - 1]))))
          starts.push_back(i);
      const bool text = !starts.empty() && original.find('\0') == std::string::npos;
      if (text) {
        static const char* huge[] = {
            "99999999999999999999", "4294967296", "2147483648", "-1", "1e308", "nan"};
        const std::size_t at = starts[rng.below(starts.size())];
        std::size_t end = at;
        while (end < b.size() && !std::isspace(static_cast<unsigned char>(b[end]))) ++end;
        b.replace(at, end - at, huge[rng.below(6)]);
      } else {
        const std::size_t width = rng.below(2) == 0 ? 4 : 8;
        const std::size_t at = lo + rng.below(span);
        const bool ones = rng.below(2) == 0;
        for (std::size_t i = 0; i < width && at + i < b.size(); ++i)
          b[at + i] = static_cast<char>(ones ? 0xff : (i + 1 == width ? 0x7f : 0xff));
      }
      break;
    }
  }
  return b;
}

}  // namespace taskmap::test

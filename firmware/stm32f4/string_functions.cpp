// The C string and memory functions the image calls, small instead of fast: newlib-nano's
// memcpy, memset, strlen, strncmp and memcmp take 920 B; these take about a quarter of that.
// memcpy and memset move words while both ends are word-aligned, then the odd bytes (the tick
// copies a 130-byte path that way). The other three only ever
// see parameter names and command words of a few bytes.
//
// Built with -fno-lto -fno-tree-loop-distribute-patterns (CMakeLists.txt): otherwise GCC
// recognises each loop as the very function it implements and compiles it into a call to itself.

#include <cstddef>
#include <cstdint>

namespace {

using Word = std::uint32_t __attribute__((may_alias));
struct __attribute__((may_alias)) Block {
  Word words[4];
};

bool word_aligned(std::uintptr_t bits) {
  return (bits & (sizeof(Word) - 1u)) == 0u;
}

}  // namespace

extern "C" {

void* memcpy(void* destination, const void* source, std::size_t size) {
  auto* out = static_cast<unsigned char*>(destination);
  const auto* in = static_cast<const unsigned char*>(source);
  std::size_t done = 0u;
  if (word_aligned(reinterpret_cast<std::uintptr_t>(out) | reinterpret_cast<std::uintptr_t>(in))) {
    for (; done + sizeof(Block) <= size; done += sizeof(Block)) {  // ldm/stm of four words
      *reinterpret_cast<Block*>(out + done) = *reinterpret_cast<const Block*>(in + done);
    }
    for (; done + sizeof(Word) <= size; done += sizeof(Word)) {
      *reinterpret_cast<Word*>(out + done) = *reinterpret_cast<const Word*>(in + done);
    }
  }
  for (; done < size; ++done) {
    out[done] = in[done];
  }
  return destination;
}

void* memset(void* destination, int value, std::size_t size) {
  auto* out = static_cast<unsigned char*>(destination);
  const auto byte = static_cast<unsigned char>(value);
  std::size_t done = 0u;
  if (word_aligned(reinterpret_cast<std::uintptr_t>(out))) {
    const Word word = 0x01010101u * byte;
    for (; done + sizeof(Word) <= size; done += sizeof(Word)) {
      *reinterpret_cast<Word*>(out + done) = word;
    }
  }
  for (; done < size; ++done) {
    out[done] = byte;
  }
  return destination;
}

std::size_t strlen(const char* text) {
  std::size_t length = 0u;
  while (text[length] != '\0') {
    ++length;
  }
  return length;
}

int memcmp(const void* a, const void* b, std::size_t size) {
  const auto* left = static_cast<const unsigned char*>(a);
  const auto* right = static_cast<const unsigned char*>(b);
  for (std::size_t i = 0u; i < size; ++i) {
    if (left[i] != right[i]) {
      return left[i] < right[i] ? -1 : 1;
    }
  }
  return 0;
}

int strncmp(const char* a, const char* b, std::size_t size) {
  for (std::size_t i = 0u; i < size; ++i) {
    const auto left = static_cast<unsigned char>(a[i]);
    const auto right = static_cast<unsigned char>(b[i]);
    if (left != right) {
      return left < right ? -1 : 1;
    }
    if (left == '\0') {
      return 0;
    }
  }
  return 0;
}

}  // extern "C"

#include "translator/text.h"

namespace ctb {

namespace {

// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is not valid.
std::size_t SequenceLength(std::string_view text, std::size_t i) {
  auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n;
  unsigned int cp;
  if (c >= 0xC2 && c <= 0xDF)
    n = 2, cp = c & 0x1F;
  else if (c >= 0xE0 && c <= 0xEF)
    n = 3, cp = c & 0x0F;
  else if (c >= 0xF0 && c <= 0xF4)
    n = 4, cp = c & 0x07;
  else
    return 0;
  if (i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((b(i + k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b(i + k) & 0x3F);
  }
  if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)) ||
      (cp >= 0xD800 && cp <= 0xDFFF))
    return 0;
  return n;
}

const char kReplacement[] = "\xEF\xBF\xBD";

}  // namespace

std::string ValidUtf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    std::size_t n = SequenceLength(text, i);
    if (n == 0) {
      out += kReplacement;
      ++i;
    } else {
      out.append(text.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string Cut(std::string_view text, std::size_t max_chars) {
  std::string valid = ValidUtf8(text);
  std::size_t chars = 0, i = 0;
  while (i < valid.size() && chars < max_chars) {
    i += SequenceLength(valid, i);
    ++chars;
  }
  if (i >= valid.size()) return valid;
  return valid.substr(0, i) + "...";
}

std::string Around(std::string_view text, std::size_t at, std::size_t radius) {
  if (at > text.size()) at = text.size();
  // Step back `radius` code points (continuation bytes do not count).
  std::size_t start = at, steps = 0;
  while (start > 0 && steps < radius) {
    --start;
    if ((static_cast<unsigned char>(text[start]) & 0xC0) != 0x80) ++steps;
  }
  std::string before = ValidUtf8(text.substr(start, at - start));
  std::string after = Cut(text.substr(at), radius);
  if (after.size() >= 3 && after.compare(after.size() - 3, 3, "...") == 0)
    after.resize(after.size() - 3);
  std::string out =
      (start > 0 ? "..." : "") + before + after + (at + after.size() < text.size() ? "..." : "");
  for (auto& c : out)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  return out;
}

std::string Excerpt(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return ValidUtf8(text);
  std::size_t head = max_bytes * 2 / 3, tail = max_bytes - head;
  // Keep code points whole: move the cuts off continuation bytes.
  while (head > 0 && (static_cast<unsigned char>(text[head]) & 0xC0) == 0x80) --head;
  std::size_t tail_start = text.size() - tail;
  while (tail_start < text.size() && (static_cast<unsigned char>(text[tail_start]) & 0xC0) == 0x80)
    ++tail_start;
  return ValidUtf8(text.substr(0, head)) + "\n[... " + std::to_string(tail_start - head) +
         " bytes left out ...]\n" + ValidUtf8(text.substr(tail_start));
}

std::string MaskedSecret(const std::string& secret) {
  if (secret.empty()) return "(none)";
  if (secret.size() <= 8) return "****";
  return secret.substr(0, 3) + "..." + secret.substr(secret.size() - 4);
}

std::string MaskSecret(std::string text, const std::string& secret) {
  if (secret.empty()) return text;
  const std::string masked = MaskedSecret(secret);
  std::size_t pos = 0;
  while ((pos = text.find(secret, pos)) != std::string::npos) {
    text.replace(pos, secret.size(), masked);
    pos += masked.size();
  }
  return text;
}

}  // namespace ctb

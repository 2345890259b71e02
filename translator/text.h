// Text shown to people and sent back to the LLM: always valid UTF-8, bounded, and never holding
// the API key. Pure functions, thread-safe.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ctb {

// text with every invalid UTF-8 sequence replaced by U+FFFD, so that JSON serialisation of it
// never throws.
std::string ValidUtf8(std::string_view text);

// At most max_chars code points of text (valid UTF-8 first); a cut is marked with "...".
std::string Cut(std::string_view text, std::size_t max_chars = 200);

// The text around byte offset `at` (up to `radius` code points either side), for quoting the
// place of a syntax error; valid UTF-8, newlines shown as spaces.
std::string Around(std::string_view text, std::size_t at, std::size_t radius = 40);

// A bounded excerpt of a long text: the whole text when it has at most max_bytes bytes, else
// its head and tail with a note of how much was left out. Valid UTF-8.
std::string Excerpt(std::string_view text, std::size_t max_bytes);

// text with every occurrence of secret replaced by its masked form ("sk-...abcd", or "****"
// for short secrets). An empty secret changes nothing.
std::string MaskSecret(std::string text, const std::string& secret);
std::string MaskedSecret(const std::string& secret);

}  // namespace ctb

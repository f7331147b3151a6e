#pragma once
/// \file
/// Locale-independent reading of text mesh files from a memory buffer that need not end in
/// NUL: a cursor that never reads past the end and counts lines, and parsers of decimal
/// numbers and integers. Used by mesh_io.hpp; no heap, no exceptions, no C locale.
///
/// Numbers. grammar: [+-] (digits [. digits] | . digits) [(e|E) [+-] digits]. The text
/// "nan", "inf" or "infinity" (any case, any sign) is reported as NonFinite, as is a value
/// that overflows. Conversion: up to 19 significant digits are kept (later ones dropped).
/// When the significand is below 2^53 and the decimal exponent within +-22 (every number
/// printf's %g, %e or %f writes with up to 15 digits) the value is the correctly rounded
/// double: one exact power of ten, one rounding. Otherwise it is within a few units in the
/// last place. The same text always gives the same value, which is what welding needs.

#include <cstddef>
#include <cstdint>

namespace grip {
namespace detail {

/// Outcome of parsing one number.
enum class NumberParse { Ok, Malformed, NonFinite };

/// True for the blanks of a line (space, tab, CR, form feed, vertical tab).
constexpr bool is_text_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
/// True for a blank or a newline.
constexpr bool is_text_space(char c) { return is_text_blank(c) || c == '\n'; }
/// ASCII lower case of c.
constexpr char ascii_lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

/// True if [b, e) equals the lower-case word w, ignoring ASCII case.
inline bool equals_word(const char* b, const char* e, const char* w) {
  for (; b < e; ++b, ++w)
    if (*w == '\0' || ascii_lower(*b) != *w) return false;
  return *w == '\0';
}

/// True if [b, e) starts with the lower-case word w, ignoring case.
inline bool starts_with_word(const char* b, const char* e, const char* w) {
  for (; *w != '\0'; ++b, ++w)
    if (b >= e || ascii_lower(*b) != *w) return false;
  return true;
}

/// 10^k for 0 <= k <= 310 by binary powering (infinite beyond 10^308).
inline double power_of_ten(long k) {
  static constexpr double binary[9] = {1e1, 1e2, 1e4, 1e8, 1e16, 1e32, 1e64, 1e128, 1e256};
  double scale = 1.0;
  for (int i = 0; i < 9; ++i)
    if (k & (1L << i)) scale *= binary[i];
  return scale;
}

/// Parses the whole of [b, e) as a decimal number into `value` (finite when Ok).
inline NumberParse parse_real(const char* b, const char* e, double& value) {
  value = 0.0;
  const char* s = b;
  bool negative = false;
  if (s < e && (*s == '+' || *s == '-')) negative = *s++ == '-';
  if (starts_with_word(s, e, "nan") || starts_with_word(s, e, "inf")) return NumberParse::NonFinite;
  std::uint64_t mant = 0;
  int kept = 0;
  long exp10 = 0;
  bool digits = false;
  for (; s < e && *s >= '0' && *s <= '9'; ++s) {
    digits = true;
    const unsigned d = static_cast<unsigned>(*s - '0');
    if (mant == 0 && d == 0) continue;
    if (kept < 19) {
      mant = mant * 10 + d;
      ++kept;
    } else {
      ++exp10;
    }
  }
  if (s < e && *s == '.') {
    ++s;
    for (; s < e && *s >= '0' && *s <= '9'; ++s) {
      digits = true;
      const unsigned d = static_cast<unsigned>(*s - '0');
      if (mant == 0 && d == 0) {
        --exp10;
      } else if (kept < 19) {
        mant = mant * 10 + d;
        ++kept;
        --exp10;
      }
    }
  }
  if (!digits) return NumberParse::Malformed;
  if (s < e && (*s == 'e' || *s == 'E')) {
    ++s;
    bool eneg = false;
    if (s < e && (*s == '+' || *s == '-')) eneg = *s++ == '-';
    if (!(s < e && *s >= '0' && *s <= '9')) return NumberParse::Malformed;
    long x = 0;
    for (; s < e && *s >= '0' && *s <= '9'; ++s)
      if (x < 100000) x = x * 10 + (*s - '0');
    exp10 += eneg ? -x : x;
  }
  if (s != e) return NumberParse::Malformed;
  if (mant == 0) {
    value = negative ? -0.0 : 0.0;
    return NumberParse::Ok;
  }
  // mant < 10^19: the value is below 10^(19 + exp10); beyond 10^309 it overflows.
  if (exp10 > 310) return NumberParse::NonFinite;
  if (exp10 < -400) {
    value = negative ? -0.0 : 0.0;
    return NumberParse::Ok;
  }
  static constexpr double exact[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  double v = static_cast<double>(mant);
  if (exp10 >= 0 && exp10 <= 22) {
    v *= exact[exp10];
  } else if (exp10 < 0 && exp10 >= -22) {
    v /= exact[-exp10];
  } else if (exp10 > 0) {
    v *= power_of_ten(exp10);  // exp10 <= 310: infinite beyond 10^308, as the value is
  } else {
    long k = -exp10;
    if (k > 300) {
      v /= 1e300;
      k -= 300;
    }
    v /= power_of_ten(k);
  }
  if (!(v <= 1.7976931348623157e308)) return NumberParse::NonFinite;
  value = negative ? -v : v;
  return NumberParse::Ok;
}

/// Parses an optionally signed decimal integer at the start of [b, e); `next` receives the
/// first character after it. Magnitudes beyond 10^12 saturate there. False if no digit.
inline bool parse_integer(const char* b, const char* e, long long& value, const char*& next) {
  const char* s = b;
  bool negative = false;
  if (s < e && (*s == '+' || *s == '-')) negative = *s++ == '-';
  long long v = 0;
  const char* d0 = s;
  for (; s < e && *s >= '0' && *s <= '9'; ++s)
    if (v < 1000000000000LL) v = v * 10 + (*s - '0');
  next = s;
  value = negative ? -v : v;
  return s != d0;
}

/// A read position in a buffer of `size` bytes with the current 1-based line.
struct TextCursor {
  const char* data;  ///< The buffer.
  std::size_t size;  ///< Its size.
  std::size_t pos;   ///< Next byte.
  long line;         ///< Line of `pos`, 1-based.

  /// Starts at the beginning, after a UTF-8 byte-order mark if present.
  TextCursor(const char* d, std::size_t n) : data(d), size(d == nullptr ? 0 : n), pos(0), line(1) {
    if (size >= 3 && static_cast<unsigned char>(data[0]) == 0xEF && static_cast<unsigned char>(data[1]) == 0xBB &&
        static_cast<unsigned char>(data[2]) == 0xBF)
      pos = 3;
  }
  /// True at the end of the buffer.
  bool end() const { return pos >= size; }
  /// Skips blanks; with `newlines` also newlines (counting them).
  void skip_blanks(bool newlines) {
    while (pos < size && (is_text_blank(data[pos]) || (newlines && data[pos] == '\n'))) {
      if (data[pos] == '\n') ++line;
      ++pos;
    }
  }
  /// Moves past the next newline (or to the end).
  void skip_line() {
    while (pos < size && data[pos] != '\n') ++pos;
    if (pos < size) {
      ++pos;
      ++line;
    }
  }
  /// The next token on this line (after blanks): [b, e) up to a blank, newline, '#' (when
  /// `comments`) or the end. False (b == e) if the line has no more token.
  bool token(const char*& b, const char*& e, bool comments) {
    skip_blanks(false);
    b = data + pos;
    while (pos < size && !is_text_space(data[pos]) && !(comments && data[pos] == '#')) ++pos;
    e = data + pos;
    return b != e;
  }
  /// The next token across lines (after blanks and newlines). False at the end.
  bool next_token(const char*& b, const char*& e) {
    skip_blanks(true);
    return token(b, e, false);
  }
};

}  // namespace detail
}  // namespace grip

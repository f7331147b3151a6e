// Runs an example and checks what it prints and writes (CTest tests example_<name>,
// examples/CMakeLists.txt). Usage:
//   grip_example_check [checks] -- EXAMPLE [ARGS...]
// checks, each as often as wanted:
//   --expect REGEX          the output (stdout and stderr) must contain a match (ECMAScript)
//   --reject REGEX          the output must contain none
//   --csv FILE ROWS TEXT    FILE (written by the example in the working directory) has a
//                           header and exactly ROWS data rows, every row as many fields as the
//                           header, every field a finite number except in the columns named in
//                           TEXT (comma-separated, "-" for none)
//   --svg FILE MIN          FILE is well-formed XML (every element closed in order, attributes
//                           quoted, only the five predefined entities or character references)
//                           whose root element is <svg>, with at least MIN elements in all
// The example must exit 0. Exit status 0 if every check holds, 1 otherwise (each failure is
// printed). The example's output is kept as <EXAMPLE name>.out in the working directory.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

int failures = 0;

void fail(const std::string& what) {
  std::printf("FAILED: %s\n", what.c_str());
  ++failures;
}

bool read_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  text = s.str();
  return true;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : line) {
    if (ch == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(cur);
  return out;
}

bool finite_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

void check_csv(const std::string& path, long rows, const std::string& text_columns) {
  std::string text;
  if (!read_file(path, text)) return fail("cannot read " + path);
  std::vector<std::string> lines = split(text, '\n');
  if (!lines.empty() && lines.back().empty()) lines.pop_back();
  if (lines.empty()) return fail(path + " is empty");
  const std::vector<std::string> header = split(lines[0], ',');
  const std::vector<std::string> texts = text_columns == "-" ? std::vector<std::string>{} : split(text_columns, ',');
  std::vector<bool> is_text(header.size(), false);
  for (const std::string& t : texts) {
    bool found = false;
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == t) is_text[c] = found = true;
    if (!found) fail(path + ": no column named " + t);
  }
  if (static_cast<long>(lines.size()) - 1 != rows)
    fail(path + ": " + std::to_string(lines.size() - 1) + " data rows, expected " + std::to_string(rows));
  int bad = 0;
  for (std::size_t r = 1; r < lines.size() && bad < 5; ++r) {
    const std::vector<std::string> f = split(lines[r], ',');
    if (f.size() != header.size()) {
      fail(path + " row " + std::to_string(r) + ": " + std::to_string(f.size()) + " fields, header has " +
           std::to_string(header.size()));
      ++bad;
      continue;
    }
    for (std::size_t c = 0; c < f.size(); ++c)
      if (!is_text[c] && !finite_number(f[c])) {
        fail(path + " row " + std::to_string(r) + " column " + header[c] + ": '" + f[c] + "' is not a finite number");
        ++bad;
        break;
      }
  }
}

// A minimal well-formedness check of XML: enough to tell a truncated or mis-escaped SVG.
void check_svg(const std::string& path, long min_elements) {
  std::string s;
  if (!read_file(path, s)) return fail("cannot read " + path);
  std::vector<std::string> open;
  long elements = 0;
  std::string root;
  std::size_t i = 0;
  auto error = [&](const std::string& what) {
    fail(path + " at byte " + std::to_string(i) + ": " + what);
    i = s.size() + 1;
  };
  auto name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == ':' || c == '.';
  };
  auto entity_ok = [&](std::size_t at) {  // s[at] == '&'
    const std::size_t semi = s.find(';', at);
    if (semi == std::string::npos || semi - at > 10) return false;
    const std::string e = s.substr(at + 1, semi - at - 1);
    if (e == "amp" || e == "lt" || e == "gt" || e == "quot" || e == "apos") return true;
    return e.size() > 1 && e[0] == '#';
  };
  while (i < s.size()) {
    if (s[i] != '<') {
      if (s[i] == '&' && !entity_ok(i)) error("bad entity");
      if (open.empty() && !std::isspace(static_cast<unsigned char>(s[i]))) error("text outside the root element");
      ++i;
      continue;
    }
    if (s.compare(i, 4, "<!--") == 0) {
      const std::size_t e = s.find("-->", i + 4);
      if (e == std::string::npos) return error("unterminated comment");
      i = e + 3;
      continue;
    }
    if (s.compare(i, 2, "<?") == 0) {
      const std::size_t e = s.find("?>", i + 2);
      if (e == std::string::npos) return error("unterminated declaration");
      i = e + 2;
      continue;
    }
    const bool closing = i + 1 < s.size() && s[i + 1] == '/';
    std::size_t j = i + (closing ? 2 : 1);
    const std::size_t name_start = j;
    while (j < s.size() && name_char(s[j])) ++j;
    const std::string name = s.substr(name_start, j - name_start);
    if (name.empty()) return error("tag without a name");
    if (closing) {
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      if (j >= s.size() || s[j] != '>') return error("bad closing tag </" + name);
      if (open.empty() || open.back() != name) return error("</" + name + "> does not close the open element");
      open.pop_back();
      i = j + 1;
      continue;
    }
    // attributes: name = 'value' or "value"
    bool self_closing = false;
    for (;;) {
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      if (j >= s.size()) return error("unterminated tag <" + name);
      if (s[j] == '>') break;
      if (s.compare(j, 2, "/>") == 0) {
        self_closing = true;
        ++j;
        break;
      }
      const std::size_t a = j;
      while (j < s.size() && name_char(s[j])) ++j;
      if (j == a) return error("bad attribute in <" + name);
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      if (j >= s.size() || s[j] != '=') return error("attribute without a value in <" + name);
      ++j;
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      if (j >= s.size() || (s[j] != '"' && s[j] != '\'')) return error("unquoted attribute in <" + name);
      const char q = s[j];
      const std::size_t e = s.find(q, j + 1);
      if (e == std::string::npos) return error("unterminated attribute in <" + name);
      for (std::size_t k = j + 1; k < e; ++k) {
        if (s[k] == '<') return error("'<' in an attribute of <" + name);
        if (s[k] == '&' && !entity_ok(k)) return error("bad entity in an attribute of <" + name);
      }
      j = e + 1;
    }
    if (open.empty()) {
      if (!root.empty()) return error("a second root element <" + name);
      root = name;
    }
    ++elements;
    if (!self_closing) open.push_back(name);
    i = j + 1;
  }
  if (i > s.size()) return;  // an error was reported
  if (!open.empty()) return fail(path + ": <" + open.back() + "> never closed");
  if (root != "svg") fail(path + ": the root element is <" + root + ">, not <svg>");
  if (elements < min_elements)
    fail(path + ": " + std::to_string(elements) + " elements, expected at least " + std::to_string(min_elements));
}

}  // namespace

int main(int argc, char** argv) {
  int k = 1;
  std::vector<std::string> expect, reject;
  struct Csv {
    std::string file;
    long rows;
    std::string text;
  };
  struct Svg {
    std::string file;
    long min;
  };
  std::vector<Csv> csvs;
  std::vector<Svg> svgs;
  for (; k < argc && std::strcmp(argv[k], "--") != 0; ++k) {
    const std::string opt = argv[k];
    if (opt == "--expect" && k + 1 < argc)
      expect.push_back(argv[++k]);
    else if (opt == "--reject" && k + 1 < argc)
      reject.push_back(argv[++k]);
    else if (opt == "--csv" && k + 3 < argc) {
      csvs.push_back(Csv{argv[k + 1], std::strtol(argv[k + 2], nullptr, 10), argv[k + 3]});
      k += 3;
    } else if (opt == "--svg" && k + 2 < argc) {
      svgs.push_back(Svg{argv[k + 1], std::strtol(argv[k + 2], nullptr, 10)});
      k += 2;
    } else {
      std::printf(
          "usage: grip_example_check [--expect RE] [--reject RE] [--csv FILE ROWS TEXT] [--svg FILE MIN] -- EXAMPLE\n");
      return 2;
    }
  }
  if (k + 1 >= argc) {
    std::printf("no example given after --\n");
    return 2;
  }
  std::string exe = argv[k + 1];
  const std::size_t slash = exe.find_last_of('/');
  const std::string out_file = (slash == std::string::npos ? exe : exe.substr(slash + 1)) + ".out";
  std::string command = "'" + exe + "'";
  for (int a = k + 2; a < argc; ++a) command += std::string(" '") + argv[a] + "'";
  for (const Csv& c : csvs) std::remove(c.file.c_str());  // what the example writes, not a stale copy
  for (const Svg& c : svgs) std::remove(c.file.c_str());
  const int status = std::system((command + " > '" + out_file + "' 2>&1").c_str());
  std::string output;
  read_file(out_file, output);
  std::fputs(output.c_str(), stdout);
  if (status != 0) fail("the example exited with status " + std::to_string(status));
  for (const std::string& re : expect)
    if (!std::regex_search(output, std::regex(re))) fail("no match in the output for /" + re + "/");
  for (const std::string& re : reject)
    if (std::regex_search(output, std::regex(re))) fail("the output matches /" + re + "/");
  for (const Csv& c : csvs) check_csv(c.file, c.rows, c.text);
  for (const Svg& c : svgs) check_svg(c.file, c.min);
  std::printf("%s: %d check(s) failed\n", exe.c_str(), failures);
  return failures == 0 ? 0 : 1;
}

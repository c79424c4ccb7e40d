// SPDX-License-Identifier: GPL-3.0-or-later
// Every function of the readers and writers in io/formats is at most 80 lines long (from the line of its
// opening brace to that of its closing one), so that each reads as a header step or a data step. The
// lengths come from a small brace matcher over the source text, itself checked on hand-made snippets.
#include "support/test_env.h"

#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr int kMaxLines = 80;

struct FunctionSpan {
  std::string head; // the text before the opening brace, trimmed to its last line
  int firstLine = 0, lastLine = 0;
  int lines() const { return lastLine - firstLine + 1; }
};

// `text` with comments, string and character literals (raw strings too) blanked out, newlines kept.
std::string blankCommentsAndLiterals(const std::string& s) {
  std::string out = s;
  const auto blank = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to && k < out.size(); ++k)
      if (out[k] != '\n') out[k] = ' ';
  };
  std::size_t i = 0;
  while (i < s.size()) {
    if (s.compare(i, 2, "//") == 0) {
      const std::size_t e = std::min(s.find('\n', i), s.size());
      blank(i, e);
      i = e;
    } else if (s.compare(i, 2, "/*") == 0) {
      const std::size_t e = std::min(s.find("*/", i + 2), s.size() - 2) + 2;
      blank(i, e);
      i = e;
    } else if (s[i] == 'R' && i + 1 < s.size() && s[i + 1] == '"') {
      const std::size_t open = s.find('(', i);
      const std::string close = ")" + s.substr(i + 2, open - i - 2) + "\"";
      const std::size_t e = std::min(s.find(close, open), s.size()) + close.size();
      blank(i + 1, e);
      i = e;
    } else if (s[i] == '"' ||
               (s[i] == '\'' && !(i > 0 && std::isxdigit(static_cast<unsigned char>(s[i - 1])) &&
                                  i + 1 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1]))))) {
      // (a quote between hex digits is a digit separator, 1'000)
      const char q = s[i];
      std::size_t e = i + 1;
      while (e < s.size() && s[e] != q && s[e] != '\n')
        e += s[e] == '\\' ? 2 : 1;
      blank(i + 1, e);
      i = e + 1;
    } else {
      ++i;
    }
  }
  return out;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\n");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\n") - b + 1);
}

// The function bodies of a C++ source: the outermost brace blocks (outside any function) whose head ends
// in a parameter list, with qualifiers, a trailing return type or a constructor's initialiser list after
// it. A constructor whose initialisers use braces is one span from the first of them to the body's end.
std::vector<FunctionSpan> functionSpans(const std::string& source) {
  const std::string t = blankCommentsAndLiterals(source);
  static const std::regex keyword(
      R"(^(if|for|while|switch|catch|else|do|try|namespace|struct|class|enum|union|extern)\b)");
  static const std::regex signature(R"(\)[^;{}()]*$|\)\s*:.*$)");
  static const std::regex continuation(R"(^(,\s*[\w:]+\s*)?$)");
  std::vector<FunctionSpan> spans;
  struct Open {
    bool function;
    int line;
  };
  std::vector<Open> stack;
  std::size_t boundary = 0; // where the head of the next block at the current level starts
  int line = 1, functionDepth = -1;
  bool lastWasFunction = false;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const char c = t[i];
    if (c == '\n') ++line;
    if (functionDepth >= 0) { // inside a function: only find its end
      if (c == '{') stack.push_back({false, line});
      if (c == '}') {
        stack.pop_back();
        if (static_cast<int>(stack.size()) == functionDepth) {
          spans.back().lastLine = line;
          functionDepth = -1;
          boundary = i + 1;
          lastWasFunction = true;
        }
      }
      continue;
    }
    if (c == ';') {
      boundary = i + 1;
      lastWasFunction = false;
    } else if (c == '}') {
      if (!stack.empty()) stack.pop_back();
      boundary = i + 1;
      lastWasFunction = false;
    } else if (c == '{') {
      std::string head = trimmed(t.substr(boundary, i - boundary));
      const bool isFunction = !std::regex_search(head, keyword) && std::regex_search(head, signature);
      if (lastWasFunction && std::regex_match(head, continuation)) {
        functionDepth = static_cast<int>(stack.size()); // the body after brace initialisers: the same span
        stack.push_back({true, line});
        continue;
      }
      stack.push_back({isFunction, line});
      if (isFunction) {
        const auto nl = head.rfind('\n');
        spans.push_back({nl == std::string::npos ? head : head.substr(nl + 1), line, line});
        functionDepth = static_cast<int>(stack.size()) - 1;
      } else {
        boundary = i + 1;
        lastWasFunction = false;
      }
    }
  }
  return spans;
}

std::string repeatLines(int n) {
  std::string s;
  for (int k = 0; k < n; ++k)
    s += "  x += 1;\n";
  return s;
}

} // namespace

TEST(FunctionLength, ScannerMeasuresBodies) {
  // Two free functions, braces in strings, comments and lambdas inside, a namespace and a struct around.
  const std::string src =
      "namespace a {\nstruct S {\n  int f() const { return 1; }\n};\n"
      "int g(int x) {\n  auto l = [](int y) { return y; }; // }\n  const char* s = \"}{\";\n"
      "  char q = '}';\n" +
      repeatLines(81 - 6) + "  return l(x);\n}\n} // namespace a\n";
  const auto spans = functionSpans(src);
  ASSERT_EQ(spans.size(), 2u);
  EXPECT_EQ(spans[0].lines(), 1);
  EXPECT_EQ(spans[1].lines(), 81);
  EXPECT_NE(spans[1].head.find("int g(int x)"), std::string::npos) << spans[1].head;
}

TEST(FunctionLength, ScannerJoinsBraceInitialisersToTheBody) {
  const std::string src = "A::A(int n)\n    : v{n}, w{2} {\n" + repeatLines(3) +
                          "}\nconst int kTable[] = {1, 2};\n"
                          "int h() { return kTable[0]; }\n";
  const auto spans = functionSpans(src);
  ASSERT_EQ(spans.size(), 2u);
  EXPECT_EQ(spans[0].firstLine, 2);
  EXPECT_EQ(spans[0].lastLine, 6);
  EXPECT_EQ(spans[1].lines(), 1);
}

TEST(FunctionLength, ReadersAndWritersStayShort) {
  const fs::path dir = dtf::test::sourceDir() / "io" / "formats";
  int files = 0, functions = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".cpp") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    for (const FunctionSpan& f : functionSpans(text.str())) {
      EXPECT_LE(f.lines(), kMaxLines) << entry.path().filename().string() << ":" << f.firstLine << " "
                                      << f.head << " is " << f.lines() << " lines long";
      ++functions;
    }
    ++files;
  }
  EXPECT_GE(files, 10) << "io/formats holds fewer reader sources than expected: is the tree where expected?";
  EXPECT_GE(functions, 150);
}

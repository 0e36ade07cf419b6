/// @file
/// odocal-doc-tables: writes, or checks, the tables of the docs that come from the lists declared
/// once in core: docs/console.md's table of every command form (ODOCAL_CONSOLE_FORMS) and
/// docs/parameters.md's table of parameters (ODOCAL_DRIVE_PARAMETERS). Each table sits between
/// two marker comments; the tool replaces what lies between them and leaves the rest of the page
/// as it is. The parameters' "what" column is prose: it is kept, by name, from the page.
///
///   odocal-doc-tables --check SOURCE_DIR   exit 1, naming the page, when a table is stale
///   odocal-doc-tables --write SOURCE_DIR   rewrite the tables in place
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "odocal/console/commands.hpp"
#include "odocal/params/param_table.hpp"

namespace {

using odocal::console::Changes;
using odocal::drive::FactorGroup;
using odocal::params::ParamId;

constexpr std::string_view kNoWhat = "(not described yet: write what it does)";

std::string begin_marker(std::string_view table) {
  return "<!-- odocal-doc-tables " + std::string(table) + " begin: generated, do not edit -->";
}
std::string end_marker(std::string_view table) {
  return "<!-- odocal-doc-tables " + std::string(table) + " end -->";
}

ParamId param(std::size_t i) {
  return static_cast<ParamId>(i);
}

/// The parameters of a factor group, as a list of code spans.
std::string group_members(FactorGroup group) {
  std::string names;
  for (std::size_t i = 0; i < odocal::params::param_count; ++i) {
    const auto& info = odocal::params::param_info(param(i));
    if (info.group == group) {
      names += (names.empty() ? "`" : ", `") + std::string(info.name) + "`";
    }
  }
  return names;
}

std::string changes_text(Changes changes) {
  switch (changes) {
    case Changes::nothing:
      return "no parameter";
    case Changes::named:
      return "the parameter it names";
    case Changes::wheel:
      return "the wheel factors: " + group_members(FactorGroup::wheel);
    case Changes::lateral:
      return "the lateral factors: " + group_members(FactorGroup::lateral);
    case Changes::any:
      return "any parameter";
  }
  return "?";
}

std::string console_forms_table() {
  std::ostringstream out;
  out << "| form | words | question | may change |\n| --- | --: | --- | --- |\n";
  for (const auto& form : odocal::console::command_forms) {
    std::string synopsis = form.synopsis;  // a `|` inside a table cell is escaped, code or not
    for (std::size_t at = synopsis.find('|'); at != std::string::npos;
         at = synopsis.find('|', at + 2)) {
      synopsis.insert(at, "\\");
    }
    out << "| `" << synopsis << "` | " << unsigned{form.min_words};
    if (form.max_words != form.min_words) {
      out << "-" << unsigned{form.max_words};
    }
    out << " | " << (form.has(odocal::console::form_question) ? "yes" : "no") << " | "
        << changes_text(form.changes()) << " |\n";
  }
  return out.str();
}

/// A value as the docs print it: up to 6 significant digits, whole numbers from 10 000 grouped
/// by thousands with spaces.
std::string number(float value) {
  const double v = static_cast<double>(value);
  if (v == std::floor(v) && std::fabs(v) >= 10000.0) {
    std::string digits = std::to_string(static_cast<long long>(v));
    for (std::size_t at = digits.size(); at > 3; at -= 3) {
      digits.insert(at - 3, " ");
    }
    return digits;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// A unit as the docs print it: `*` as a middle dot, `s2` as s squared.
std::string unit(std::string text) {
  for (std::size_t at = text.find('*'); at != std::string::npos; at = text.find('*')) {
    text.replace(at, 1, "\u00b7");
  }
  if (text.size() >= 2 && text.compare(text.size() - 2, 2, "s2") == 0) {
    text.replace(text.size() - 1, 1, "\u00b2");
  }
  return text;
}

std::string group_name(FactorGroup group) {
  switch (group) {
    case FactorGroup::none:
      return "";
    case FactorGroup::wheel:
      return "wheel";
    case FactorGroup::lateral:
      return "lateral";
  }
  return "?";
}

/// The cells of a Markdown table row (a `|` inside a code span is not a separator).
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  bool code = false;
  for (std::size_t i = 1; i < row.size(); ++i) {
    const char ch = row[i];
    if (ch == '`') {
      code = !code;
    }
    if (ch == '|' && !code && row[i - 1] != '\\') {
      const auto first = cell.find_first_not_of(' ');
      const auto last = cell.find_last_not_of(' ');
      out.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
      cell.clear();
    } else {
      cell += ch;
    }
  }
  return out;
}

/// The "what" column of the current table, by parameter name.
std::map<std::string, std::string> whats(const std::string& current) {
  std::map<std::string, std::string> by_name;
  std::istringstream lines(current);
  for (std::string line; std::getline(lines, line);) {
    const std::vector<std::string> row = cells(line);
    if (row.size() >= 3 && row[1].size() > 2 && row[1].front() == '`') {
      by_name[row[1].substr(1, row[1].size() - 2)] = row.back();
    }
  }
  return by_name;
}

std::string parameters_table(const std::string& current) {
  const std::map<std::string, std::string> what = whats(current);
  const odocal::params::ParamSet defaults = odocal::params::default_params();
  std::ostringstream out;
  out << "| id | name | unit | default | min | max | group | what |\n"
         "| --: | --- | --- | --: | --: | --: | --- | --- |\n";
  for (std::size_t i = 0; i < odocal::params::param_count; ++i) {
    const auto& info = odocal::params::param_info(param(i));
    const auto found = what.find(info.name);
    out << "| " << i << " | `" << info.name << "` | " << unit(info.unit) << " | "
        << number(defaults.get(param(i))) << " | " << number(info.min) << " | " << number(info.max)
        << " | " << group_name(info.group) << " | "
        << (found != what.end() ? found->second : std::string(kNoWhat)) << " |\n";
  }
  return out.str();
}

struct Page {
  std::string path;
  std::string table;  ///< the marker's name
  std::string (*make)(const std::string& current);
};

bool read(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return false;
  }
  std::ostringstream all;
  all << in.rdbuf();
  text = all.str();
  return true;
}

/// Checks or rewrites one page. @return 0 when it is (now) current, 1 when stale, 2 on an error.
int process(const std::string& root, const Page& page, bool write) {
  const std::string path = root + "/" + page.path;
  std::string text;
  if (!read(path, text)) {
    std::cerr << path << ": cannot read\n";
    return 2;
  }
  const std::string begin = begin_marker(page.table) + "\n";
  const std::string end = end_marker(page.table);
  const auto from = text.find(begin);
  const auto to = from == std::string::npos ? from : text.find(end, from);
  if (from == std::string::npos || to == std::string::npos) {
    std::cerr << path << ": no '" << begin_marker(page.table) << "' ... '" << end
              << "' pair to put the table between\n";
    return 2;
  }
  const std::string current = text.substr(from + begin.size(), to - from - begin.size());
  const std::string wanted = page.make(current);
  if (wanted.find(kNoWhat) != std::string::npos) {
    std::cerr << path << ": a parameter has no description in the table's 'what' column\n";
  }
  if (current == wanted && wanted.find(kNoWhat) == std::string::npos) {
    return 0;
  }
  if (!write) {
    std::cerr << path << ": the " << page.table
              << " table is not what the list in core declares; run "
                 "build/host/bin/odocal-doc-tables --write . and review the diff\n";
    return 1;
  }
  if (current != wanted) {
    text.replace(from + begin.size(), current.size(), wanted);
    const std::string temporary = path + ".new";
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      out << text;
      if (!out.flush()) {
        std::cerr << temporary << ": cannot write\n";
        return 2;
      }
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
      std::cerr << path << ": cannot replace\n";
      return 2;
    }
    std::cerr << "wrote the " << page.table << " table of " << path << "\n";
  }
  return wanted.find(kNoWhat) == std::string::npos ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc == 3 ? argv[1] : "";
  if (mode != "--check" && mode != "--write") {
    std::cerr << "usage: odocal-doc-tables --check|--write SOURCE_DIR\n";
    return 2;
  }
  const Page pages[] = {
      {"docs/console.md", "console-forms",
       [](const std::string&) { return console_forms_table(); }},
      {"docs/parameters.md", "parameters", parameters_table},
  };
  int worst = 0;
  for (const Page& page : pages) {
    const int result = process(argv[2], page, mode == "--write");
    worst = result > worst ? result : worst;
  }
  return worst;
}

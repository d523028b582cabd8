// The grid of a sweep: value lists, seeds, shards, sweep files and the
// manifest (DIR/sweep.xml).
#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "apps/colony/sweep.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxSeeds = 10'000'000;

// The manifest's run_folders values.
constexpr const char* kByValues = "by-values";
constexpr const char* kNumbered = "numbered";

// A whole number in [0, max] or UsageError naming `what`.
uint64_t ParseCount(const std::string& what, const std::string& text, uint64_t max) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] == '-' || *end != '\0' || errno == ERANGE || v > max) {
    throw UsageError(what + ": '" + text + "' is not accepted; expected a whole number in [0, " +
                     std::to_string(max) + "]");
  }
  return v;
}

std::string Where(const std::string& file, const tinyxml2::XMLElement* e) {
  return file + ":" + std::to_string(e->GetLineNum()) + ": <" + e->Name() + ">";
}

// Rejects attributes of `e` not in `known`.
void CheckAttributes(const std::string& file, const tinyxml2::XMLElement* e,
                     const std::set<std::string>& known) {
  for (const auto* a = e->FirstAttribute(); a; a = a->Next()) {
    if (!known.contains(a->Name())) {
      std::string accepted;
      for (const auto& k : known) accepted += (accepted.empty() ? "" : ", ") + k;
      throw UsageError(Where(file, e) + ": unknown attribute '" + a->Name() +
                       "'; accepted: " + accepted);
    }
  }
}

// A value as part of a folder name: letters, digits, '.', '+' and '-' as
// they are, every other byte %XX, so that '_' and '=' only ever separate.
std::string Encode(const std::string& value) {
  std::string out;
  for (const char c : value) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '.' || c == '+' || c == '-') {
      out += c;
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", u);
      out += hex;
    }
  }
  return out;
}

// The last word of a --set path: "quantity" for
// arena.distribute.entity.quantity, "mode" for
// controllers.x[m].params.mode. Only a label (the parameters' order tells
// them apart): characters unfit for a file name become '-'.
std::string ShortName(const std::string& path) {
  std::string word = path.substr(path.find_last_of('.') + 1);
  word = word.substr(0, word.find('['));
  for (char& c : word) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '-';
  }
  return word.empty() ? "param" : word;
}

// A <param path="..." values="..."/> or <param path="..."><value>...</value>...</param>.
Param ReadParamElement(const std::string& file, const tinyxml2::XMLElement* e) {
  CheckAttributes(file, e, {"path", "values"});
  Param p;
  const char* path = e->Attribute("path");
  if (!path || !*path) throw UsageError(Where(file, e) + ": needs a 'path' attribute");
  p.path = path;
  const std::string what = Where(file, e) + " '" + p.path + "'";
  if (const char* values = e->Attribute("values")) {
    if (e->FirstChildElement()) {
      throw UsageError(what + ": give either a 'values' attribute or <value> elements");
    }
    p.values = ParseValueList(what, values);
    return p;
  }
  for (const auto* v = e->FirstChildElement(); v; v = v->NextSiblingElement()) {
    if (std::string(v->Name()) != "value") {
      throw UsageError(Where(file, v) + ": unknown element; <param> holds <value> elements");
    }
    p.values.push_back(Trim(v->GetText() ? v->GetText() : ""));
  }
  if (p.values.empty()) throw UsageError(what + ": empty value list");
  std::set<std::string> seen;
  for (const auto& v : p.values) {
    if (v.empty()) throw UsageError(what + ": a <value> is empty");
    if (!seen.insert(v).second) throw UsageError(what + ": value '" + v + "' is given twice");
  }
  return p;
}

}  // namespace

size_t Grid::size() const {
  size_t n = seeds.size();
  for (const auto& p : params) n *= p.values.size();
  return n;
}

RunSpec RunAt(const Grid& grid, size_t index) {
  RunSpec run;
  run.index = index;
  run.seed = grid.seeds[index % grid.seeds.size()];
  size_t rest = index / grid.seeds.size();
  run.values.resize(grid.params.size());
  for (size_t k = grid.params.size(); k-- > 0;) {
    const auto& values = grid.params[k].values;
    run.values[k] = values[rest % values.size()];
    rest /= values.size();
  }
  if (grid.run_folders == RunFolders::kNumbered) {
    const size_t width = std::max<size_t>(4, std::to_string(grid.size() - 1).size());
    const std::string number = std::to_string(index);
    run.name = std::string(width - std::min(width, number.size()), '0') + number;
  } else {
    run.name = RunName(grid, run.values, run.seed);
  }
  return run;
}

std::string RunName(const Grid& grid, const std::vector<std::string>& values, uint64_t seed) {
  std::string name;
  for (size_t k = 0; k < grid.params.size(); ++k) {
    name += ShortName(grid.params[k].path) + "=" + Encode(values[k]) + "_";
  }
  name += "seed=" + std::to_string(seed);
  // File names hold at most 255 bytes; long ones keep their start and a hash.
  constexpr size_t kLongest = 200;
  if (name.size() > kLongest) name = name.substr(0, kLongest - 17) + "_" + HashText(name);
  return name;
}

std::string Slice::ToString() const {
  return std::to_string(index + 1) + "/" + std::to_string(count);
}

std::vector<std::string> ParseValueList(const std::string& what, const std::string& text) {
  if (Trim(text).empty()) throw UsageError(what + ": empty value list");
  const auto values = SplitList(text, text.find(';') != std::string::npos ? ';' : ',');
  std::set<std::string> seen;
  for (const auto& v : values) {
    if (v.empty()) throw UsageError(what + ": empty value in '" + text + "'");
    if (!seen.insert(v).second) throw UsageError(what + ": value '" + v + "' is given twice");
  }
  return values;
}

Param ParseParam(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw UsageError("--param '" + text +
                     "': expected PATH=V1,V2,..., e.g. arena.distribute.entity.quantity=10,50");
  }
  Param p;
  p.path = Trim(text.substr(0, eq));
  p.values = ParseValueList("--param " + p.path, text.substr(eq + 1));
  return p;
}

std::vector<uint64_t> ParseSeeds(const std::string& text) {
  const std::string what = "--seeds '" + text + "'";
  if (Trim(text).empty()) throw UsageError(what + ": empty seed list");
  std::vector<uint64_t> seeds;
  std::set<uint64_t> seen;
  for (const auto& item : SplitList(text, ',')) {
    if (item.empty()) throw UsageError(what + ": empty item; expected e.g. 1..30, 1,2,5 or 1..3,7");
    const size_t dots = item.find("..");
    const uint64_t first = ParseCount(what, item.substr(0, dots), INT64_MAX);
    const uint64_t last =
        dots == std::string::npos ? first : ParseCount(what, item.substr(dots + 2), INT64_MAX);
    if (last < first) throw UsageError(what + ": range '" + item + "' ends before it starts");
    if (last - first >= kMaxSeeds || seeds.size() + (last - first) >= kMaxSeeds) {
      throw UsageError(what + ": more than " + std::to_string(kMaxSeeds) + " seeds");
    }
    for (uint64_t s = first;; ++s) {
      if (!seen.insert(s).second) {
        throw UsageError(what + ": seed " + std::to_string(s) + " is given twice");
      }
      seeds.push_back(s);
      if (s == last) break;
    }
  }
  return seeds;
}

std::string FormatSeeds(const std::vector<uint64_t>& seeds) {
  std::string out;
  for (size_t i = 0; i < seeds.size();) {
    size_t j = i;
    while (j + 1 < seeds.size() && seeds[j + 1] == seeds[j] + 1) ++j;
    out += (out.empty() ? "" : ",") + std::to_string(seeds[i]);
    if (j > i) out += ".." + std::to_string(seeds[j]);
    i = j + 1;
  }
  return out;
}

Slice ParseShard(const std::string& text) {
  const size_t slash = text.find('/');
  const std::string what = "--shard '" + text + "'";
  if (slash == std::string::npos) {
    throw UsageError(what + ": expected I/N with 1 <= I <= N, e.g. 3/10");
  }
  const uint64_t i = ParseCount(what, text.substr(0, slash), 1'000'000);
  const uint64_t n = ParseCount(what, text.substr(slash + 1), 1'000'000);
  if (n < 1 || i < 1 || i > n) {
    throw UsageError(what + ": expected I/N with 1 <= I <= N, e.g. 3/10");
  }
  return {i - 1, n};
}

double ParseTimeout(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v <= 0) {
    throw UsageError("--timeout: '" + text + "' is not accepted; expected seconds > 0, e.g. 600");
  }
  return v;
}

bool IsSweepFile(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) return false;
  return doc.RootElement() && std::string(doc.RootElement()->Name()) == "sweep";
}

namespace {

// A manifest's <code colony_version="..."><file path="..." sha256="..."/>...</code>.
Code ReadCodeElement(const std::string& file, const tinyxml2::XMLElement* e) {
  CheckAttributes(file, e, {"colony_version", "fingerprint"});
  Code code;
  code.colony_version = e->Attribute("colony_version") ? e->Attribute("colony_version") : "";
  for (const auto* f = e->FirstChildElement(); f; f = f->NextSiblingElement()) {
    if (std::string(f->Name()) != "file") {
      throw UsageError(Where(file, f) + ": unknown element; <code> holds <file> elements");
    }
    CheckAttributes(file, f, {"path", "sha256"});
    const char* path = f->Attribute("path");
    const char* sha256 = f->Attribute("sha256");
    if (!path || !sha256) throw UsageError(Where(file, f) + ": needs 'path' and 'sha256'");
    code.files.push_back({path, sha256});
  }
  return code;
}

// A sweep file, or a manifest (which also says how its run folders are
// named and holds <code>; both are ignored when it is used as a sweep file).
struct SweepXml {
  SweepFile file;
  std::optional<RunFolders> run_folders;
};

SweepXml ReadSweepXml(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw UsageError(path + ": cannot read the sweep file: " + doc.ErrorStr());
  }
  const auto* root = doc.RootElement();
  CheckAttributes(path, root, {"experiment", "experiment_hash", "seeds", "timeout", "run_folders"});
  SweepXml xml;
  SweepFile& file = xml.file;
  const char* experiment = root->Attribute("experiment");
  if (!experiment || !*experiment) {
    throw UsageError(Where(path, root) + ": needs an 'experiment' attribute");
  }
  // The experiment is named relative to the sweep file.
  file.grid.experiment =
      fs::absolute(fs::path(path).parent_path() / experiment).lexically_normal().string();
  if (const char* hash = root->Attribute("experiment_hash")) file.grid.experiment_hash = hash;
  if (const char* seeds = root->Attribute("seeds")) file.grid.seeds = ParseSeeds(seeds);
  if (const char* timeout = root->Attribute("timeout")) file.timeout = ParseTimeout(timeout);
  if (const char* folders = root->Attribute("run_folders")) {
    const std::string f = folders;
    if (f != kByValues && f != kNumbered) {
      throw UsageError(Where(path, root) + ": run_folders '" + f + "' is not accepted; expected " +
                       kByValues + " or " + kNumbered);
    }
    xml.run_folders = f == kByValues ? RunFolders::kByValues : RunFolders::kNumbered;
  }
  std::set<std::string> paths;
  for (const auto* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string name = e->Name();
    if (name == "code" && !file.code) {
      file.code = ReadCodeElement(path, e);
      continue;
    }
    if (name != "param") {
      throw UsageError(Where(path, e) + ": unknown element; <sweep> holds <param> elements");
    }
    file.grid.params.push_back(ReadParamElement(path, e));
    if (!paths.insert(file.grid.params.back().path).second) {
      throw UsageError(Where(path, e) + ": parameter '" + file.grid.params.back().path +
                       "' is given twice");
    }
  }
  return xml;
}

// FNV-1a, 64 bits, over `n` bytes, continuing from `h`.
uint64_t Fnv1a(uint64_t h, const char* bytes, size_t n) {
  for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
  return h;
}
constexpr uint64_t kFnvStart = 14695981039346656037ull;

std::string Hex(uint64_t h) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

}  // namespace

SweepFile ReadSweepFile(const std::string& path) { return ReadSweepXml(path).file; }

std::string HashFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(path + ": no such file or not readable");
  uint64_t h = kFnvStart;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    h = Fnv1a(h, buffer, static_cast<size_t>(in.gcount()));
  }
  return Hex(h);
}

std::string HashText(const std::string& text) {
  return Hex(Fnv1a(kFnvStart, text.data(), text.size()));
}

void WriteManifest(const std::string& dir, const Manifest& manifest) {
  const Grid& grid = manifest.grid;
  tinyxml2::XMLDocument doc;
  doc.InsertEndChild(
      doc.NewComment(" Written by colony sweep: the runs of this folder. Run the same sweep "
                     "command again to resume it. "));
  auto* root = doc.NewElement("sweep");
  doc.InsertEndChild(root);
  root->SetAttribute("experiment", grid.experiment.c_str());
  root->SetAttribute("experiment_hash", grid.experiment_hash.c_str());
  root->SetAttribute("seeds", FormatSeeds(grid.seeds).c_str());
  root->SetAttribute("run_folders",
                     grid.run_folders == RunFolders::kByValues ? kByValues : kNumbered);
  for (const auto& p : grid.params) {
    auto* e = root->InsertNewChildElement("param");
    e->SetAttribute("path", p.path.c_str());
    for (const auto& v : p.values) e->InsertNewChildElement("value")->SetText(v.c_str());
  }
  if (manifest.code) {
    root->InsertNewComment(
        " The code the runs are made with: a resumed sweep compares it with its own. ");
    auto* code = root->InsertNewChildElement("code");
    code->SetAttribute("colony_version", manifest.code->colony_version.c_str());
    code->SetAttribute("fingerprint", manifest.code->Fingerprint().c_str());
    for (const auto& f : manifest.code->files) {
      auto* e = code->InsertNewChildElement("file");
      e->SetAttribute("path", f.path.c_str());
      e->SetAttribute("sha256", f.sha256.c_str());
    }
  }
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  WriteAtomically((fs::path(dir) / "sweep.xml").string(), printer.CStr());
}

Manifest ReadManifest(const std::string& dir) {
  const std::string path = (fs::path(dir) / "sweep.xml").string();
  if (!fs::exists(path)) throw UsageError(dir + ": not a sweep folder (no sweep.xml)");
  SweepXml xml = ReadSweepXml(path);
  Manifest manifest{std::move(xml.file.grid), std::move(xml.file.code)};
  if (manifest.grid.seeds.empty()) throw UsageError(path + ": names no seeds");
  // Manifests written before run folders were named by values say nothing.
  manifest.grid.run_folders = xml.run_folders.value_or(RunFolders::kNumbered);
  return manifest;
}

namespace {

std::string Describe(const std::vector<std::string>& values) {
  const bool commas = std::any_of(values.begin(), values.end(), [](const std::string& v) {
    return v.find(',') != std::string::npos;
  });
  return Join(values, commas ? ";" : ",");
}

}  // namespace

std::string GridDifference(const Grid& found, const Grid& wanted) {
  if (found.experiment != wanted.experiment) {
    return "it runs " + found.experiment + ", not " + wanted.experiment;
  }
  if (!found.experiment_hash.empty() && !wanted.experiment_hash.empty() &&
      found.experiment_hash != wanted.experiment_hash) {
    return "the experiment file has changed since it started";
  }
  auto paths = [](const std::vector<Param>& params) {
    std::vector<std::string> out;
    for (const auto& p : params) out.push_back(p.path);
    return out;
  };
  if (paths(found.params) != paths(wanted.params)) {
    auto describe = [](const std::vector<std::string>& p) {
      return p.empty() ? std::string("no parameters") : Join(p);
    };
    return "it sweeps " + describe(paths(found.params)) + ", not " + describe(paths(wanted.params));
  }
  return "";
}

std::string GridChange(const Grid& found, const Grid& wanted) {
  std::vector<std::string> changes;
  if (found.seeds != wanted.seeds) {
    changes.push_back("seeds " + FormatSeeds(found.seeds) + " -> " + FormatSeeds(wanted.seeds));
  }
  for (size_t k = 0; k < found.params.size() && k < wanted.params.size(); ++k) {
    if (found.params[k].values != wanted.params[k].values) {
      changes.push_back(found.params[k].path + " " + Describe(found.params[k].values) + " -> " +
                        Describe(wanted.params[k].values));
    }
  }
  return Join(changes, "; ");
}

}  // namespace colony::sweep

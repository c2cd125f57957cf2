// An MJCF model's XML (mjcf_document.hpp): TinyXML documents with <include>s expanded within
// the limits of mjcf_model.hpp, element locations, <default> classes and attribute lookup.
#include "mjcf_document.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <utility>

#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/xml_scan.hpp"
#include "taskmap/hands/mjcf_model.hpp"

namespace taskmap::detail {
namespace {

namespace fs = std::filesystem;

/// Start tags in xml: an upper bound on its elements (comments and quoted '<' may add a few).
std::size_t startTags(const std::string& xml) {
  std::size_t n = 0;
  for (std::size_t i = xml.find('<'); i != std::string::npos; i = xml.find('<', i + 1))
    if (i + 1 < xml.size() &&
        (std::isalpha(static_cast<unsigned char>(xml[i + 1])) != 0 || xml[i + 1] == '_'))
      ++n;
  return n;
}

/// True when `inner` (canonical) lies inside the folder `outer` (canonical).
bool inside(const fs::path& inner, const fs::path& outer) {
  const fs::path rel = inner.lexically_relative(outer);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

MjcfDocument::MjcfDocument(const std::string& xml, const std::string& path) : path_(path) {
  if (xml.size() > kMaxMjcfFileBytes)
    throw Error("MJCF '" + path + "': " + std::to_string(xml.size()) + " bytes, more than the " +
                std::to_string(kMaxMjcfFileBytes >> 20) + " MiB an MJCF hand may have; refused");
  std::error_code ec;
  folder_ = fs::weakly_canonical(fs::absolute(path, ec).parent_path(), ec).string();
  root_ = parse(xml, path, nullptr);
  if (std::string(root_->Value()) != "mujoco")
    fail(root_, "the top element is not <mujoco>: not an MJCF model (a URDF's is <robot>)");
  expandIncludes(root_, 1);
}

const TiXmlElement* MjcfDocument::parse(const std::string& xml, const std::string& file,
                                        const TiXmlElement* included_by) {
  const std::string W =
      included_by ? where(included_by) + ": included file '" + file + "'" : "MJCF '" + file + "'";
  if (files_.size() >= kMaxMjcfFiles)
    throw Error(W + ": more than " + std::to_string(kMaxMjcfFiles) +
                " files in the model; refused");
  const XmlShape shape = scanXml(xml, kMaxMjcfDepth);
  if (shape.max_depth > kMaxMjcfDepth)
    throw Error(W + ": XML elements nested more than " + std::to_string(kMaxMjcfDepth) +
                " deep; refused before parsing (an MJCF hand is a few dozen levels deep)");
  elements_ += startTags(xml);
  if (elements_ > kMaxMjcfElements)
    throw Error(W + ": the model has more than " + std::to_string(kMaxMjcfElements) +
                " XML elements; refused before parsing (a hand has a few hundred)");
  auto doc = std::make_unique<TiXmlDocument>(file.c_str());
  doc->Parse(xml.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc->Error())
    throw Error(W + ": malformed XML at line " + std::to_string(doc->ErrorRow()) + ": " +
                doc->ErrorDesc());
  const TiXmlElement* top = doc->RootElement();
  if (!top) throw Error(W + ": no XML element");
  docs_.push_back(std::move(doc));
  files_.push_back(file);
  return top;
}

void MjcfDocument::expandIncludes(const TiXmlElement* top, int depth) {
  // Walk the file's elements with an explicit stack; each <include> loads its file once.
  std::vector<std::pair<const TiXmlElement*, int>> stack{{top, depth}};
  while (!stack.empty()) {
    const auto [e, d] = stack.back();
    stack.pop_back();
    for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::string(c->Value()) != "include") {
        stack.emplace_back(c, d + 1);
        continue;
      }
      const char* file = c->Attribute("file");
      if (!file || !*file) fail(c, "<include> needs a file attribute");
      std::error_code ec;
      const fs::path p = fs::weakly_canonical(fs::path(folder_) / file, ec);
      if (ec || !inside(p, folder_))
        fail(c, "included file '" + std::string(file) + "' is outside the model's folder '" +
                    folder_ + "'; refused (copy it into the model's folder)");
      for (const std::string& seen : files_) {
        std::error_code ec2;
        if (fs::weakly_canonical(seen, ec2) == p)
          fail(c, "'" + std::string(file) +
                      "' is included a second time (a cycle of includes, or one file included "
                      "twice; MuJoCo refuses both)");
      }
      const std::string text =
          readRegularFile(p.string(), where(c) + ": included file", kMaxMjcfFileBytes);
      const TiXmlElement* included = parse(text, p.string(), c);
      includes_[c] = included;
      // The included file's top element is replaced by its children, at the include's depth.
      expandIncludes(included, d);
    }
  }
}

std::vector<const TiXmlElement*> MjcfDocument::children(const TiXmlElement* e) const {
  std::vector<const TiXmlElement*> out;
  for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const auto it = includes_.find(c);
    if (it == includes_.end()) {
      out.push_back(c);
      continue;
    }
    for (const TiXmlElement* i : children(it->second)) out.push_back(i);
  }
  return out;
}

std::vector<const TiXmlElement*> MjcfDocument::children(const TiXmlElement* e,
                                                        const char* tag) const {
  std::vector<const TiXmlElement*> out;
  for (const TiXmlElement* c : children(e))
    if (std::string(c->Value()) == tag) out.push_back(c);
  return out;
}

std::string MjcfDocument::where(const TiXmlElement* e) const {
  std::string s = "MJCF '" + path_ + "': <" + e->Value();
  if (const char* n = e->Attribute("name")) s += " name='" + std::string(n) + "'";
  s += "> at line " + std::to_string(e->Row());
  const TiXmlDocument* d = e->GetDocument();
  if (d && d->Value() != path_) s += " of '" + std::string(d->Value()) + "'";
  return s;
}

void MjcfDocument::fail(const TiXmlElement* e, const std::string& what) const {
  throw Error(where(e) + ": " + what);
}

MjcfDefaults::MjcfDefaults(const MjcfDocument& doc) : doc_(doc) {
  for (const TiXmlElement* d : doc.children(doc.root(), "default")) read(doc, d, -1, 1);
}

void MjcfDefaults::read(const MjcfDocument& doc, const TiXmlElement* d, int parent, int depth) {
  if (depth > kMaxMjcfDepth) doc.fail(d, "<default> classes nested too deep");
  const char* cls = d->Attribute("class");
  if (parent >= 0 && !cls) doc.fail(d, "a nested <default> needs a class attribute");
  const std::string name = cls ? cls : "main";
  if (!index_.emplace(name, static_cast<int>(classes_.size())).second)
    doc.fail(d, "default class '" + name + "' is defined twice");
  const int me = static_cast<int>(classes_.size());
  classes_.push_back({name, parent, {}});
  for (const TiXmlElement* c : doc.children(d)) {
    if (std::string(c->Value()) == "default")
      read(doc, c, me, depth + 1);
    else
      classes_[static_cast<std::size_t>(me)].elements.push_back(c);
  }
}

int MjcfDefaults::classNamed(const std::string& name, const TiXmlElement* e) const {
  const auto it = index_.find(name);
  if (it == index_.end()) doc_.fail(e, "names default class '" + name + "', which is not defined");
  return it->second;
}

int MjcfDefaults::classOf(const TiXmlElement* e, int inherited) const {
  const char* cls = e->Attribute("class");
  return cls ? classNamed(cls, e) : inherited;
}

std::optional<MjcfAttr> MjcfDefaults::find(const TiXmlElement* e,
                                           const std::vector<const char*>& tags, int cls,
                                           const char* name) const {
  if (const char* v = e->Attribute(name)) return MjcfAttr{v, e};
  for (int c = cls; c >= 0; c = classes_[static_cast<std::size_t>(c)].parent) {
    const auto& elements = classes_[static_cast<std::size_t>(c)].elements;
    for (auto it = elements.rbegin(); it != elements.rend(); ++it)
      for (const char* tag : tags)
        if (std::string((*it)->Value()) == tag)
          if (const char* v = (*it)->Attribute(name)) return MjcfAttr{v, *it};
  }
  return std::nullopt;
}

std::vector<MjcfAttr> MjcfDefaults::findAll(const TiXmlElement* e,
                                            const std::vector<const char*>& tags, int cls,
                                            const char* name) const {
  std::vector<MjcfAttr> out;
  if (const char* v = e->Attribute(name)) out.push_back({v, e});
  for (int c = cls; c >= 0; c = classes_[static_cast<std::size_t>(c)].parent) {
    const auto& elements = classes_[static_cast<std::size_t>(c)].elements;
    for (auto it = elements.rbegin(); it != elements.rend(); ++it)
      for (const char* tag : tags)
        if (std::string((*it)->Value()) == tag)
          if (const char* v = (*it)->Attribute(name)) out.push_back({v, *it});
  }
  return out;
}

std::vector<double> mjcfNumbers(const MjcfDocument& doc, const MjcfAttr& a, const char* name,
                                std::size_t min_count, std::size_t max_count) {
  std::vector<double> out;
  const char* p = a.text.c_str();
  while (true) {
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
    if (!*p) break;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v) || errno == ERANGE)
      doc.fail(a.at, std::string(name) + "=\"" + a.text + "\" is not a list of finite numbers");
    out.push_back(v);
    if (out.size() > max_count) break;
    p = end;
  }
  if (out.size() < min_count || out.size() > max_count)
    doc.fail(a.at, std::string(name) + "=\"" + a.text + "\" needs " +
                       (min_count == max_count
                            ? std::to_string(min_count)
                            : std::to_string(min_count) + " to " + std::to_string(max_count)) +
                       " numbers");
  return out;
}

int mjcfBool(const MjcfDocument& doc, const MjcfAttr& a, const char* name, bool allow_auto) {
  if (a.text == "true") return 1;
  if (a.text == "false") return 0;
  if (allow_auto && a.text == "auto") return -1;
  doc.fail(a.at, std::string(name) + "=\"" + a.text + "\" must be true or false" +
                     (allow_auto ? " or auto" : ""));
}

}  // namespace taskmap::detail

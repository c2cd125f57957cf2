#pragma once
// Private to hands: an MJCF model's XML as TinyXML documents, <include>s expanded (bounded,
// inside the model's folder, each file once), element locations for messages, and the
// <default> classes with the attribute lookup of an element through its class chain.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <tinyxml.h>

namespace taskmap::detail {

/// The model's files, parsed, with <include> elements resolved to the included <mujoco> roots.
class MjcfDocument {
 public:
  /// Parses `xml` (the text of the file `path`) and every file it includes. Throws Error naming
  /// the file and line on malformed XML, a root that is not <mujoco>, an include outside the
  /// model's folder, included twice (or in a cycle), or any limit of mjcf_model.hpp exceeded.
  MjcfDocument(const std::string& xml, const std::string& path);

  /// The main file's <mujoco> element.
  const TiXmlElement* root() const { return root_; }
  /// Child elements of e in document order, each <include> replaced by the included file's
  /// top-level elements (recursively).
  std::vector<const TiXmlElement*> children(const TiXmlElement* e) const;
  /// children(e) named `tag`.
  std::vector<const TiXmlElement*> children(const TiXmlElement* e, const char* tag) const;
  /// "MJCF '<path>': <tag name='n'> at line L[ of '<file>']".
  std::string where(const TiXmlElement* e) const;
  /// Throws Error(where(e) + ": " + what).
  [[noreturn]] void fail(const TiXmlElement* e, const std::string& what) const;
  /// The main file as given.
  const std::string& path() const { return path_; }
  /// "MJCF '<path>': ", the prefix of messages about the model as a whole.
  std::string prefix() const { return "MJCF '" + path_ + "': "; }
  /// Every file read, the main one first.
  const std::vector<std::string>& files() const { return files_; }

 private:
  const TiXmlElement* parse(const std::string& xml, const std::string& file,
                            const TiXmlElement* included_by);
  void expandIncludes(const TiXmlElement* top, int depth);

  std::string path_;
  std::string folder_;  // canonical folder of the main file
  std::vector<std::unique_ptr<TiXmlDocument>> docs_;
  std::vector<std::string> files_;
  std::map<const TiXmlElement*, const TiXmlElement*> includes_;  // <include> -> its <mujoco>
  std::size_t elements_ = 0;
  const TiXmlElement* root_ = nullptr;
};

/// An attribute's text and the element that gave it (the element itself or a default).
struct MjcfAttr {
  std::string text;
  const TiXmlElement* at = nullptr;
};

/// The <default> classes of a model: "main" (the top-level <default>) and its nested classes.
class MjcfDefaults {
 public:
  /// Reads every top-level <default> of doc. Throws Error on a nested <default> without a
  /// class, a repeated class name, or nesting beyond kMaxMjcfDepth.
  explicit MjcfDefaults(const MjcfDocument& doc);
  /// The class an element names with its `class` attribute, else `inherited` (a childclass in
  /// scope, or main()). Throws Error when the class does not exist.
  int classOf(const TiXmlElement* e, int inherited) const;
  /// Index of class `name` (its element e is named in messages); throws Error when unknown.
  int classNamed(const std::string& name, const TiXmlElement* e) const;
  /// The main class, -1 when the model has no <default>.
  int main() const { return classes_.empty() ? -1 : 0; }
  /// Attribute `name` of element e: its own, else from the elements named one of `tags` in class
  /// `cls` and its ancestors (the nearest class first; within a class the last element).
  std::optional<MjcfAttr> find(const TiXmlElement* e, const std::vector<const char*>& tags, int cls,
                               const char* name) const;
  /// Every definition of attribute `name` for e, nearest first (e's own, then the classes').
  std::vector<MjcfAttr> findAll(const TiXmlElement* e, const std::vector<const char*>& tags,
                                int cls, const char* name) const;

 private:
  struct Class {
    std::string name;
    int parent = -1;
    std::vector<const TiXmlElement*> elements;  // its element defaults, document order
  };
  void read(const MjcfDocument& doc, const TiXmlElement* d, int parent, int depth);
  const MjcfDocument& doc_;
  std::vector<Class> classes_;
  std::map<std::string, int> index_;
};

/// The numbers of attribute `a` (whitespace-separated, finite), between min_count and
/// max_count of them; `name` is the attribute's name. Throws Error via doc.fail otherwise.
std::vector<double> mjcfNumbers(const MjcfDocument& doc, const MjcfAttr& a, const char* name,
                                std::size_t min_count, std::size_t max_count);

/// "true" or "false" (also "auto" when allow_auto; returns -1 for it), else Error.
int mjcfBool(const MjcfDocument& doc, const MjcfAttr& a, const char* name, bool allow_auto);

}  // namespace taskmap::detail

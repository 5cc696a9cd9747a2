// pugixml helpers for the profile parsers: an XML file read with its line table (pugixml gives
// offsets, we give `file:line`), and `Ctx`, the per-file parse context that collects
// diagnostics and the references to other profiles found while parsing.
// Used by the profile parsers and the loader. Thread-safety: an XmlFile and a Ctx belong to one
// load() call; nothing is shared between calls.
#pragma once

#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <pugixml.hpp>

#include "profile/loader.hpp"
#include "profile/model.hpp"

namespace keel::profile::detail {

/// Profiles larger than this are rejected before parsing (a profile is a few kB).
inline constexpr std::size_t kMaxProfileBytes = 16u << 20;

/// One XML file, parsed, with the byte offset of each line start.
class XmlFile {
 public:
  /// Reads and parses `path`; `display` is the name used in messages. On failure returns
  /// null and either `open_error` (why the file cannot be read, e.g. "No such file or
  /// directory") or, for malformed XML, `syntax_error` (file:line: XML syntax error: ...).
  static std::unique_ptr<XmlFile> read(const std::string& path, std::string display, std::string& open_error,
                                       Diagnostic& syntax_error);

  pugi::xml_node root() const { return doc_.document_element(); }
  const pugi::xml_document& document() const { return doc_; }
  const std::string& display() const { return display_; }
  int lineOf(std::ptrdiff_t offset) const;
  Where where(pugi::xml_node node) const;

 private:
  pugi::xml_document doc_;
  std::vector<std::size_t> line_starts_;
  std::string display_;
};

/// A reference from one profile to another, found while parsing, followed by the loader.
struct Reference {
  std::string written;  // as in the file
  std::string path;     // absolute, normalised
  std::string display;  // for messages: the referencing file's display directory + written
  Where where;          // the element that holds the reference
  std::string who;      // "subcomponent 'sonar'", for messages
  std::vector<RootKind> accepted;
  std::optional<RootKind> declared;  // a subcomponent's <type>, when given
  /// A file OPRoS's engine never opened (a port's type profile): missing or unreadable, it is
  /// a warning, and nothing is checked against it.
  bool optional = false;
  /// Where else it was looked for, relative to the referencing file, when it is not at `path`
  /// (OPRoS's deployment layouts): none of them existed either.
  std::vector<std::string> also_searched;
};

/// Parse context of one file.
class Ctx {
 public:
  /// References resolve against the directory of the file as it was named (display path),
  /// like #include; the resulting paths are then made absolute and canonical. Errors go to
  /// `diags`, warnings to `warnings`.
  Ctx(const XmlFile& file, Diagnostics& diags, Diagnostics& warnings);

  const XmlFile& file() const { return file_; }
  Where where(pugi::xml_node node) const { return file_.where(node); }
  void error(pugi::xml_node at, std::string message);
  void error(const Where& at, std::string message);
  std::size_t errorCount() const { return diags_.size(); }
  void warn(pugi::xml_node at, std::string message);
  void warn(const Where& at, std::string message);
  /// An item (`<exports>`, `attribute 'layout' of <subcomponent>`) keel accepts and does not
  /// act on: "ITEM accepted, not used: WHY", once per item and file, at its first line; finish()
  /// adds how many more the file has.
  void unused(pugi::xml_node at, const std::string& item, std::string_view why);
  /// Completes the file's `unused` warnings; call once, after parsing.
  void finish();

  /// Resolves `written` against this file's directory and records the reference.
  /// Returns the absolute path, or an empty string (after reporting) if `written` is empty.
  /// `elsewhere`: other places to look, relative to this file's directory, in order, when the
  /// file is not where `written` says (OPRoS's layouts); the first that exists is used.
  std::string reference(pugi::xml_node at, std::string_view written, std::string who, std::vector<RootKind> accepted,
                        std::optional<RootKind> declared = std::nullopt, std::vector<std::string> elsewhere = {});
  /// As reference(), for a file whose absence is a warning (Reference::optional); an empty
  /// `written` is no reference.
  std::string optionalReference(pugi::xml_node at, std::string_view written, std::string who, RootKind accepted);
  std::vector<Reference>& references() { return refs_; }

 private:
  const XmlFile& file_;
  std::filesystem::path abs_dir_;
  std::filesystem::path display_dir_;
  Diagnostics& diags_;
  Diagnostics& warnings_;
  struct Unused {
    std::size_t index;  // in warnings_
    int more = 0;
  };
  std::map<std::string, Unused, std::less<>> unused_;
  std::vector<Reference> refs_;
  // written → canonical path: a package names one component profile for many subcomponents,
  // and each weakly_canonical costs a system call per path element.
  std::unordered_map<std::string, std::string> resolved_;
};

/// How one child element of a container is read.
struct Child {
  std::string_view name;
  std::function<void(pugi::xml_node)> read;  // empty: accepted, not read (see `unused`)
  bool repeat = false;                       // may appear more than once
  /// With no `read`: why keel does not act on it (an `unused` warning); empty: documentation
  /// keel keeps nowhere and warns nothing of (the OPRoS IDE's identifiers and canvas).
  std::string_view unused = {};
};

/// An element (any number of them) keel accepts and does not act on, and why.
inline Child unusedChild(std::string_view name, std::string_view why) { return Child{name, {}, true, why}; }

/// An attribute keel accepts: `unused` as for Child.
struct Attribute {
  std::string_view name;
  std::string_view unused = {};
  Attribute(const char* n) : name(n) {}  // NOLINT(google-explicit-constructor): a plain name is read
  Attribute(std::string_view n, std::string_view why) : name(n), unused(why) {}
};

/// Reads the children of `parent` by `children`: unknown elements, repeated singletons, stray
/// attributes of `parent` not in `attributes` are reported. Text between child elements is a
/// warning (OPRoS files have a `>` left after a comment: legal XML, meaning nothing); text in
/// an element of attributes only is an error.
void readChildren(Ctx& ctx, pugi::xml_node parent, std::initializer_list<Child> children,
                  std::initializer_list<Attribute> attributes = {});
/// The same, for a list made up of parts (assemblyChildren).
void readChildren(Ctx& ctx, pugi::xml_node parent, const std::vector<Child>& children,
                  std::initializer_list<Attribute> attributes = {});

/// Reports every attribute of `node` not in `allowed` (namespace declarations and prefixed
/// attributes such as xsi:schemaLocation are always allowed).
void checkAttributes(Ctx& ctx, pugi::xml_node node, std::initializer_list<Attribute> allowed);

/// The text content of a leaf element, trimmed. Child elements and attributes are reported.
std::string leafText(Ctx& ctx, pugi::xml_node node, std::initializer_list<Attribute> allowed_attributes = {});

/// The attribute's value, or nullopt if absent.
std::optional<std::string> attribute(pugi::xml_node node, const char* name);

/// The attribute's value; reports "missing attribute 'x' of <element>" if absent.
std::optional<std::string> requiredAttribute(Ctx& ctx, pugi::xml_node node, const char* name);

/// "<name>" of an element, for messages.
std::string tag(pugi::xml_node node);

}  // namespace keel::profile::detail

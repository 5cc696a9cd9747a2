// pugixml helpers with line numbers; see xml_reader.hpp.
#include "profile/xml_reader.hpp"

#include <iconv.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <map>
#include <system_error>

#include <fmt/format.h>

#include "profile/values.hpp"

namespace keel::profile::detail {
namespace {

namespace fs = std::filesystem;

/// Reads the whole file; on failure returns nullopt and the reason.
std::optional<std::string> slurp(const std::string& path, std::string& why) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec) {
    why = ec.message();
    return std::nullopt;
  }
  if (!fs::is_regular_file(st)) {
    why = fs::is_directory(st) ? "is a directory" : "not a regular file";
    return std::nullopt;
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    why = std::error_code(errno, std::generic_category()).message();
    return std::nullopt;
  }
  std::string data;
  char buf[65536];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0 && data.size() <= kMaxProfileBytes) {
    data.append(buf, n);
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) {
    why = "read error";
    return std::nullopt;
  }
  if (data.size() > kMaxProfileBytes) {
    why = fmt::format("larger than {} MiB", kMaxProfileBytes >> 20);
    return std::nullopt;
  }
  return data;
}

/// No attribute, no element, no text but whitespace: `<topics/>`, `<app_domain></app_domain>`.
bool isEmpty(pugi::xml_node node) {
  if (node.first_attribute()) return false;
  for (pugi::xml_node c : node.children())
    if (c.type() == pugi::node_element || !trim(c.value()).empty()) return false;
  return true;
}

/// The encoding named by the XML declaration at the start of `data`, lower case; "" without one.
std::string declaredEncoding(std::string_view data) {
  if (!data.starts_with("<?xml")) return {};
  const std::string_view decl = data.substr(0, data.find("?>"));
  const auto at = decl.find("encoding");
  if (at == std::string_view::npos) return {};
  const auto open = decl.find_first_of("\"'", at);
  if (open == std::string_view::npos) return {};
  const auto close = decl.find(decl[open], open + 1);
  if (close == std::string_view::npos) return {};
  std::string name(decl.substr(open + 1, close - open - 1));
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  return name;
}

/// The length of the valid UTF-8 prefix of `s` (s.size() when all of it is).
std::size_t validUtf8Prefix(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || i + n > s.size()) return i;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return i;
    if ((n == 2 && c < 0xC2) || (n == 3 && c == 0xE0 && static_cast<unsigned char>(s[i + 1]) < 0xA0) ||
        (n == 4 && (c > 0xF4 || (c == 0xF0 && static_cast<unsigned char>(s[i + 1]) < 0x90))))
      return i;  // overlong forms and code points past U+10FFFF
    i += n;
  }
  return i;
}

/// A file's text for pugixml, and how pugixml is to read it.
struct Text {
  std::string data;
  pugi::xml_encoding encoding;
};

/// `raw` for pugixml: UTF-8 as it is (a BOM dropped); a file whose XML declaration names
/// another encoding (OPRoS's profiles say euc-kr) converted to UTF-8 with iconv; UTF-16 and
/// UTF-32 (a BOM, or their pattern of zero bytes) left to pugixml. nullopt with `why` and the
/// offset in `raw` of the problem when the bytes are not text in the encoding they claim.
std::optional<Text> toUtf8(std::string_view raw, std::string& why, std::size_t& at) {
  const bool bom = raw.starts_with("\xEF\xBB\xBF");
  const bool wide = raw.starts_with("\xFE\xFF") || raw.starts_with("\xFF\xFE") || (raw.size() > 1 && raw[0] == '\0') ||
                    (raw.size() > 1 && raw[1] == '\0');
  if (wide) return Text{std::string(raw), pugi::encoding_auto};
  std::string data(raw.substr(bom ? 3 : 0));
  const std::string encoding = declaredEncoding(data);
  const bool utf8 = encoding.empty() || encoding == "utf-8" || encoding == "utf8";
  if (!utf8) {
    iconv_t cd = iconv_open("UTF-8", encoding.c_str());
    if (cd == reinterpret_cast<iconv_t>(-1)) {  // NOLINT(performance-no-int-to-ptr): iconv_open's failure value
      why = fmt::format("its XML declaration names the encoding '{}', which this system cannot read", encoding);
      at = 0;
      return std::nullopt;
    }
    std::string out(data.size() * 4 + 16, '\0');  // no input byte becomes more than 4 of UTF-8
    char* in_p = data.data();
    std::size_t in_left = data.size();
    char* out_p = out.data();
    std::size_t out_left = out.size();
    const std::size_t r = iconv(cd, &in_p, &in_left, &out_p, &out_left);
    iconv_close(cd);
    if (r == static_cast<std::size_t>(-1)) {
      at = data.size() - in_left;
      why = fmt::format("not {} text, as its XML declaration says: byte 0x{:02X}", encoding,
                        static_cast<unsigned char>(data[at]));
      at += bom ? 3 : 0;
      return std::nullopt;
    }
    out.resize(out.size() - out_left);
    return Text{std::move(out), pugi::encoding_utf8};  // not by its declaration: that is converted
  }
  at = validUtf8Prefix(data);
  if (at != data.size()) {
    why = fmt::format(
        "not UTF-8 text: byte 0x{:02X} (name the file's encoding in its XML declaration, e.g. "
        "<?xml version=\"1.0\" encoding=\"euc-kr\"?>)",
        static_cast<unsigned char>(data[at]));
    at += bom ? 3 : 0;
    return std::nullopt;
  }
  return Text{std::move(data), pugi::encoding_utf8};
}

bool isNamespaceAttribute(std::string_view name) { return name == "xmlns" || name.find(':') != std::string_view::npos; }

}  // namespace

std::unique_ptr<XmlFile> XmlFile::read(const std::string& path, std::string display, std::string& open_error,
                                       Diagnostic& syntax_error) {
  auto raw = slurp(path, open_error);
  if (!raw) return nullptr;
  auto file = std::make_unique<XmlFile>();
  file->display_ = std::move(display);
  std::string why;
  std::size_t bad = 0;
  auto text = toUtf8(*raw, why, bad);
  if (!text) {
    const auto line = 1 + std::count(raw->begin(), raw->begin() + static_cast<std::ptrdiff_t>(bad), '\n');
    syntax_error.where = Where{file->display_, static_cast<int>(line)};
    syntax_error.message = std::move(why);
    return nullptr;
  }
  const std::string& data = text->data;
  // Lines end in LF or CRLF (both occur in OPRoS's files): either counts once, at its LF.
  file->line_starts_.push_back(0);
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (data[i] == '\n') file->line_starts_.push_back(i + 1);
  }
  const pugi::xml_parse_result res = file->doc_.load_buffer(data.data(), data.size(), pugi::parse_default,
                                                            text->encoding);
  if (!res) {
    syntax_error.where = Where{file->display_, file->lineOf(res.offset)};
    syntax_error.message = fmt::format("XML syntax error: {}", res.description());
    return nullptr;
  }
  return file;
}

int XmlFile::lineOf(std::ptrdiff_t offset) const {
  if (offset < 0) return 0;
  const auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), static_cast<std::size_t>(offset));
  return static_cast<int>(it - line_starts_.begin());
}

Where XmlFile::where(pugi::xml_node node) const { return Where{display_, lineOf(node.offset_debug())}; }

Ctx::Ctx(const XmlFile& file, Diagnostics& diags, Diagnostics& warnings)
    : file_(file), display_dir_(fs::path(file.display()).parent_path()), diags_(diags), warnings_(warnings) {
  std::error_code ec;
  abs_dir_ = fs::absolute(fs::path(file.display()), ec).parent_path();
}

void Ctx::error(pugi::xml_node at, std::string message) { error(where(at), std::move(message)); }

void Ctx::error(const Where& at, std::string message) { diags_.push_back(Diagnostic{at, std::move(message)}); }

void Ctx::warn(pugi::xml_node at, std::string message) { warn(where(at), std::move(message)); }

void Ctx::warn(const Where& at, std::string message) { warnings_.push_back(Diagnostic{at, std::move(message)}); }

void Ctx::unused(pugi::xml_node at, const std::string& item, std::string_view why) {
  const auto it = unused_.find(item);
  if (it != unused_.end()) {
    ++it->second.more;
    return;
  }
  unused_.emplace(item, Unused{warnings_.size()});
  warn(at, fmt::format("{} accepted, not used: {}", item, why));
}

void Ctx::finish() {
  for (const auto& [item, u] : unused_)
    if (u.more > 0) warnings_[u.index].message += fmt::format(" (and {} more in this file)", u.more);
  unused_.clear();
}

std::string Ctx::reference(pugi::xml_node at, std::string_view written, std::string who, std::vector<RootKind> accepted,
                           std::optional<RootKind> declared, std::vector<std::string> elsewhere) {
  if (written.empty()) {
    error(at, fmt::format("{}: empty reference", who));
    return {};
  }
  fs::path rel{std::string(written)};
  std::vector<std::string> searched;
  if (!elsewhere.empty()) {
    std::error_code ec;
    if (!fs::exists(abs_dir_ / rel, ec)) {
      const auto found = std::find_if(elsewhere.begin(), elsewhere.end(), [&](const std::string& place) {
        return fs::is_regular_file(abs_dir_ / place, ec);
      });
      if (found != elsewhere.end()) rel = *found;
      else searched = std::move(elsewhere);
    }
  }
  auto [it, fresh] = resolved_.try_emplace(rel.string());
  if (fresh) {
    std::error_code ec;
    fs::path abs = fs::weakly_canonical(abs_dir_ / rel, ec);
    if (ec) abs = (abs_dir_ / rel).lexically_normal();
    it->second = abs.string();
  }
  Reference ref;
  ref.also_searched = std::move(searched);
  ref.written = std::string(written);
  ref.path = it->second;
  ref.display = (display_dir_ / rel).lexically_normal().string();
  ref.where = where(at);
  ref.who = std::move(who);
  ref.accepted = std::move(accepted);
  ref.declared = declared;
  refs_.push_back(std::move(ref));
  return refs_.back().path;
}

std::string Ctx::optionalReference(pugi::xml_node at, std::string_view written, std::string who, RootKind accepted) {
  if (trim(written).empty()) return {};
  std::string path = reference(at, trim(written), std::move(who), {accepted});
  refs_.back().optional = true;
  return path;
}

namespace {

void readChildrenOf(Ctx& ctx, pugi::xml_node parent, const Child* first, const Child* last,
                    std::initializer_list<Attribute> attributes) {
  checkAttributes(ctx, parent, attributes);
  std::map<std::string_view, int> first_line;
  for (pugi::xml_node node : parent.children()) {
    if (node.type() == pugi::node_pcdata || node.type() == pugi::node_cdata) {
      const std::string_view text = trim(node.value());
      if (text.empty()) continue;
      if (parent.find_child([](pugi::xml_node c) { return c.type() == pugi::node_element; }))
        ctx.warn(node, fmt::format("text '{}' between the elements of {} ignored", text, tag(parent)));
      else  // an element of attributes only (<heartbeat timeout="100">fast</heartbeat>): a mistake
        ctx.error(node, fmt::format("unexpected text '{}' in {}", text, tag(parent)));
      continue;
    }
    if (node.type() != pugi::node_element) continue;
    const std::string_view name = node.name();
    const Child* const rule = std::find_if(first, last, [&](const Child& c) { return c.name == name; });
    if (rule == last) {
      ctx.error(node, fmt::format("unknown element {} in {}", tag(node), tag(parent)));
      continue;
    }
    const int line = ctx.where(node).line;
    if (!rule->repeat) {
      const auto [it, inserted] = first_line.emplace(rule->name, line);
      if (!inserted) {
        ctx.error(node, fmt::format("duplicate {} in {} (first at line {})", tag(node), tag(parent), it->second));
        continue;
      }
    }
    if (rule->read) rule->read(node);
    else if (!rule->unused.empty() && !isEmpty(node))  // an empty one has nothing to act on
      ctx.unused(node, fmt::format("{} in {}", tag(node), tag(parent)), rule->unused);
  }
}

}  // namespace

void readChildren(Ctx& ctx, pugi::xml_node parent, std::initializer_list<Child> children,
                  std::initializer_list<Attribute> attributes) {
  readChildrenOf(ctx, parent, children.begin(), children.end(), attributes);
}

void readChildren(Ctx& ctx, pugi::xml_node parent, const std::vector<Child>& children,
                  std::initializer_list<Attribute> attributes) {
  readChildrenOf(ctx, parent, children.data(), children.data() + children.size(), attributes);
}

void checkAttributes(Ctx& ctx, pugi::xml_node node, std::initializer_list<Attribute> allowed) {
  for (pugi::xml_attribute attr : node.attributes()) {
    const std::string_view name = attr.name();
    if (isNamespaceAttribute(name)) continue;
    const auto* const rule = std::find_if(allowed.begin(), allowed.end(),
                                          [&](const Attribute& a) { return a.name == name; });
    if (rule == allowed.end()) ctx.error(node, fmt::format("unknown attribute '{}' of {}", name, tag(node)));
    else if (!rule->unused.empty())
      ctx.unused(node, fmt::format("attribute '{}' of {}", name, tag(node)), rule->unused);
  }
}

std::string leafText(Ctx& ctx, pugi::xml_node node, std::initializer_list<Attribute> allowed_attributes) {
  checkAttributes(ctx, node, allowed_attributes);
  std::string text;
  for (pugi::xml_node child : node.children()) {
    if (child.type() == pugi::node_pcdata || child.type() == pugi::node_cdata) {
      text += child.value();
    } else if (child.type() == pugi::node_element) {
      ctx.error(child, fmt::format("unknown element {} in {}", tag(child), tag(node)));
    }
  }
  return std::string(trim(text));
}

std::optional<std::string> attribute(pugi::xml_node node, const char* name) {
  const pugi::xml_attribute attr = node.attribute(name);
  if (!attr) return std::nullopt;
  return std::string(attr.value());
}

std::optional<std::string> requiredAttribute(Ctx& ctx, pugi::xml_node node, const char* name) {
  auto value = attribute(node, name);
  if (!value) ctx.error(node, fmt::format("missing attribute '{}' of {}", name, tag(node)));
  return value;
}

std::string tag(pugi::xml_node node) { return fmt::format("<{}>", node.name()); }

}  // namespace keel::profile::detail

// pugixml helpers with line numbers; see xml_reader.hpp.
#include "profile/xml_reader.hpp"

#include <algorithm>
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

bool isNamespaceAttribute(std::string_view name) { return name == "xmlns" || name.find(':') != std::string_view::npos; }

}  // namespace

std::unique_ptr<XmlFile> XmlFile::read(const std::string& path, std::string display, std::string& open_error,
                                       Diagnostic& syntax_error) {
  auto data = slurp(path, open_error);
  if (!data) return nullptr;
  auto file = std::make_unique<XmlFile>();
  file->display_ = std::move(display);
  file->line_starts_.push_back(0);
  for (std::size_t i = 0; i < data->size(); ++i) {
    if ((*data)[i] == '\n') file->line_starts_.push_back(i + 1);
  }
  const pugi::xml_parse_result res = file->doc_.load_buffer(data->data(), data->size(), pugi::parse_default,
                                                            pugi::encoding_auto);
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

Ctx::Ctx(const XmlFile& file, Diagnostics& diags)
    : file_(file), display_dir_(fs::path(file.display()).parent_path()), diags_(diags) {
  std::error_code ec;
  abs_dir_ = fs::absolute(fs::path(file.display()), ec).parent_path();
}

void Ctx::error(pugi::xml_node at, std::string message) { error(where(at), std::move(message)); }

void Ctx::error(const Where& at, std::string message) { diags_.push_back(Diagnostic{at, std::move(message)}); }

std::string Ctx::reference(pugi::xml_node at, std::string_view written, std::string who, std::vector<RootKind> accepted,
                           std::optional<RootKind> declared) {
  if (written.empty()) {
    error(at, fmt::format("{}: empty reference", who));
    return {};
  }
  const fs::path rel{std::string(written)};
  auto [it, fresh] = resolved_.try_emplace(std::string(written));
  if (fresh) {
    std::error_code ec;
    fs::path abs = fs::weakly_canonical(abs_dir_ / rel, ec);
    if (ec) abs = (abs_dir_ / rel).lexically_normal();
    it->second = abs.string();
  }
  Reference ref;
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

void readChildren(Ctx& ctx, pugi::xml_node parent, std::initializer_list<Child> children,
                  std::initializer_list<std::string_view> attributes) {
  checkAttributes(ctx, parent, attributes);
  std::map<std::string_view, int> first_line;
  for (pugi::xml_node node : parent.children()) {
    if (node.type() == pugi::node_pcdata || node.type() == pugi::node_cdata) {
      const std::string_view text = trim(node.value());
      if (!text.empty()) {
        ctx.error(node, fmt::format("unexpected text '{}' in {}", text, tag(parent)));
      }
      continue;
    }
    if (node.type() != pugi::node_element) continue;
    const std::string_view name = node.name();
    const auto* const rule = std::find_if(children.begin(), children.end(),
                                          [&](const Child& c) { return c.name == name; });
    if (rule == children.end()) {
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
  }
}

void checkAttributes(Ctx& ctx, pugi::xml_node node, std::initializer_list<std::string_view> allowed) {
  for (pugi::xml_attribute attr : node.attributes()) {
    const std::string_view name = attr.name();
    if (isNamespaceAttribute(name)) continue;
    if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
    ctx.error(node, fmt::format("unknown attribute '{}' of {}", name, tag(node)));
  }
}

std::string leafText(Ctx& ctx, pugi::xml_node node, std::initializer_list<std::string_view> allowed_attributes) {
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

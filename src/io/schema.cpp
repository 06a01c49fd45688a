#include "io/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <regex>

#include "core/errors.hpp"

namespace bakesim {

extern const char* const kSceneSchemaText;  // generated from schema/scene.schema.json

using nlohmann::json;

namespace {

std::string join_path(const std::string& base, const std::string& key) { return base.empty() ? key : base + "." + key; }

// At most `limit` characters of v's JSON text, built without serialising all of
// it (a value nested 100,000 deep must not overflow the stack here).
void short_dump(const json& v, std::string& out, std::size_t limit, int depth = 0) {
  if (out.size() > limit) return;
  if (depth > 8) {
    out += "...";
    return;
  }
  if (v.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < v.size() && out.size() <= limit; ++i) {
      if (i) out += ", ";
      short_dump(v[i], out, limit, depth + 1);
    }
    out += ']';
  } else if (v.is_object()) {
    out += "{...}";
  } else {
    out += v.dump();
  }
}

std::string describe(const json& v) {
  std::string dump;
  short_dump(v, dump, 40);
  if (dump.size() > 40) dump = dump.substr(0, 37) + "...";
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return "a boolean (" + dump + ")";
    case json::value_t::string: return "a string (" + dump + ")";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return "a number (" + dump + ")";
    case json::value_t::array: return "an array (" + dump + ")";
    case json::value_t::object: return "an object";
    default: return dump;
  }
}

bool type_matches(const json& v, const std::string& t) {
  if (t == "number") return v.is_number();
  if (t == "integer")
    return v.is_number_integer() || (v.is_number_float() && v.get<double>() == std::floor(v.get<double>()));
  if (t == "string") return v.is_string();
  if (t == "boolean") return v.is_boolean();
  if (t == "array") return v.is_array();
  if (t == "object") return v.is_object();
  if (t == "null") return v.is_null();
  return false;
}

std::string article(const std::string& t) {
  if (t == "integer" || t == "array" || t == "object") return "an " + t;
  if (t == "null") return "null";
  return "a " + t;
}

std::string unit_suffix(const json& s) {
  if (s.contains("unit")) return " " + s["unit"].get<std::string>();
  return "";
}

std::string format_number(double v) { return fmt::format("{}", v); }

std::string list_strings(const json& arr) {
  std::string out;
  for (std::size_t i = 0; i < arr.size(); ++i) out += (i ? ", " : "") + arr[i].dump();
  return out;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min(
          {prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  // Accept up to a third of the word's length in edits (at least 2).
  if (best_d <= std::max<std::size_t>(2, word.size() / 3)) return best;
  return "";
}

SchemaValidator::SchemaValidator(json schema) : schema_(std::move(schema)) {}

const json& SchemaValidator::resolve(const json& s) const {
  const json* cur = &s;
  for (int guard = 0; guard < 16 && cur->is_object() && cur->contains("$ref"); ++guard) {
    const std::string ref = (*cur)["$ref"].get<std::string>();
    const std::string prefix = "#/definitions/";
    if (ref.rfind(prefix, 0) != 0) throw Error("schema: unsupported $ref " + ref);
    cur = &schema_["definitions"][ref.substr(prefix.size())];
  }
  return *cur;
}

void SchemaValidator::validate(json& doc, const std::string& file) const {
  // Keys tagged with "solvers" are read only by those solvers: refused in a
  // scene for the other one, and not filled in from their defaults.
  std::string solver;
  if (doc.is_object() && doc.contains("solver") && doc["solver"].is_object() && doc["solver"].contains("type") &&
      doc["solver"]["type"].is_string())
    solver = doc["solver"]["type"].get<std::string>();
  if (solver != "sph" && solver != "mpm") solver.clear();  // the schema reports a bad type itself
  check(doc, schema_, "", file, solver);
}

namespace {

std::string solver_title(const std::string& solver) { return solver == "sph" ? "SPH" : "MPM"; }

// Whether the chosen solver reads a property (untagged properties: both).
bool read_by(const json& property, const std::string& solver) {
  if (solver.empty() || !property.is_object() || !property.contains("solvers")) return true;
  const json& list = property["solvers"];
  return std::find(list.begin(), list.end(), solver) != list.end();
}

}  // namespace

void require_nesting_within(const json& value, int levels, const std::string& where) {
  std::vector<std::pair<const json*, int>> stack{{&value, 0}};
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    if (!node->is_structured()) continue;
    if (depth >= levels) throw InputError(where, fmt::format("nested more than {} levels deep", levels));
    for (const json& child : *node) stack.emplace_back(&child, depth + 1);
  }
}

void SchemaValidator::check(json& value, const json& schema_in, const std::string& path, const std::string& file,
                            const std::string& solver) const {
  // A scene is a few levels deep (a union of unions of shapes is the deepest
  // that means anything); a crafted file must not exhaust the stack.
  if (std::count(path.begin(), path.end(), '.') + std::count(path.begin(), path.end(), '[') > 64)
    throw InputError(file + ": " + path.substr(0, 120) + "...", "nested more than 64 levels deep");
  // Keys next to a $ref (unit, description, default) annotate the referenced schema.
  const json& s = resolve(schema_in);
  const std::string where = path.empty() ? file : file + ": " + path;
  auto fail = [&](const std::string& msg) { throw InputError(where, msg); };

  if (s.contains("oneOf")) {
    const json& alts = s["oneOf"];
    // Alternatives that are objects told apart by a constant-valued key
    // ("type" for shapes, "curve" for curves): find that key.
    std::string key;
    std::vector<std::string> kinds;
    for (const json& a : alts) {
      const json& r = resolve(a);
      if (!r.contains("properties")) break;
      std::string found;
      for (auto it = r["properties"].begin(); it != r["properties"].end(); ++it)
        if (it.value().contains("const")) found = it.key();
      if (found.empty() || (!key.empty() && found != key)) break;
      key = found;
      kinds.push_back(r["properties"][key]["const"].get<std::string>());
    }
    if (!key.empty() && kinds.size() == alts.size()) {
      if (!value.is_object()) fail("expected an object, got " + describe(value));
      if (!value.contains(key))
        fail(fmt::format("missing required key '{}' (one of: {})", key, fmt::join(kinds, ", ")));
      if (!value[key].is_string())
        throw InputError(file + ": " + join_path(path, key), "expected a string, got " + describe(value[key]));
      const std::string kind = value[key].get<std::string>();
      for (std::size_t i = 0; i < kinds.size(); ++i)
        if (kinds[i] == kind) return check(value, alts[i], path, file, solver);
      const std::string near = closest_match(kind, kinds);
      throw InputError(file + ": " + join_path(path, key),
                       fmt::format("unknown {} \"{}\"{}; allowed: {}", key, kind,
                                   near.empty() ? "" : "; did you mean \"" + near + "\"?", fmt::join(kinds, ", ")));
    }
    std::vector<std::string> wanted;
    for (const json& a : alts) {
      const json& r = resolve(a);
      const std::string t =
          r.value("type", json("any")).is_string() ? r.value("type", json("any")).get<std::string>() : "value";
      wanted.push_back(r.contains("enum") ? "one of " + list_strings(r["enum"]) : article(t));
      if (r.contains("type") && r["type"].is_string() && type_matches(value, r["type"].get<std::string>()))
        return check(value, a, path, file, solver);
    }
    fail(fmt::format("expected {}, got {}", fmt::join(wanted, " or "), describe(value)));
  }

  if (s.contains("type")) {
    const json& t = s["type"];
    bool ok = false;
    std::vector<std::string> names;
    if (t.is_string()) {
      ok = type_matches(value, t.get<std::string>());
      names.push_back(article(t.get<std::string>()));
    } else {
      for (const json& x : t) {
        ok |= type_matches(value, x.get<std::string>());
        names.push_back(article(x.get<std::string>()));
      }
    }
    if (!ok) fail(fmt::format("expected {}, got {}", fmt::join(names, " or "), describe(value)));
  }
  if (s.contains("const") && value != s["const"])
    fail(fmt::format("must be {}, got {}", s["const"].dump(), describe(value)));
  if (s.contains("enum")) {
    const json& e = s["enum"];
    if (std::find(e.begin(), e.end(), value) == e.end()) {
      std::string hint;
      if (value.is_string()) {
        std::vector<std::string> opts;
        for (const json& x : e)
          if (x.is_string()) opts.push_back(x.get<std::string>());
        const std::string near = closest_match(value.get<std::string>(), opts);
        if (!near.empty()) hint = "; did you mean \"" + near + "\"?";
      }
      fail(fmt::format("must be one of {}, got {}{}", list_strings(e), describe(value), hint));
    }
  }
  if (value.is_number()) {
    const double v = value.get<double>();
    const std::string u = unit_suffix(schema_in.contains("unit") ? schema_in : s);
    if (!std::isfinite(v)) fail("must be a finite number");
    if (s.contains("minimum") && v < s["minimum"].get<double>())
      fail(fmt::format("must be >= {}{}, got {}", format_number(s["minimum"].get<double>()), u, value.dump()));
    if (s.contains("exclusiveMinimum") && v <= s["exclusiveMinimum"].get<double>())
      fail(fmt::format("must be > {}{}, got {}", format_number(s["exclusiveMinimum"].get<double>()), u, value.dump()));
    if (s.contains("maximum") && v > s["maximum"].get<double>())
      fail(fmt::format("must be <= {}{}, got {}", format_number(s["maximum"].get<double>()), u, value.dump()));
    if (s.contains("exclusiveMaximum") && v >= s["exclusiveMaximum"].get<double>())
      fail(fmt::format("must be < {}{}, got {}", format_number(s["exclusiveMaximum"].get<double>()), u, value.dump()));
  }
  if (value.is_string()) {
    const std::string str = value.get<std::string>();
    if (s.contains("minLength") && str.size() < s["minLength"].get<std::size_t>()) fail("must not be empty");
    if (s.contains("pattern") && !std::regex_match(str, std::regex(s["pattern"].get<std::string>())))
      fail(fmt::format("\"{}\" does not match the pattern {}", str, s["pattern"].get<std::string>()));
  }
  if (value.is_array()) {
    const std::size_t n = value.size();
    if (s.contains("minItems") && s.contains("maxItems") && s["minItems"] == s["maxItems"] &&
        n != s["minItems"].get<std::size_t>())
      fail(fmt::format("expected exactly {} items, got {}", s["minItems"].get<std::size_t>(), n));
    if (s.contains("minItems") && n < s["minItems"].get<std::size_t>())
      fail(fmt::format("expected at least {} item(s), got {}", s["minItems"].get<std::size_t>(), n));
    if (s.contains("maxItems") && n > s["maxItems"].get<std::size_t>())
      fail(fmt::format("expected at most {} items, got {}", s["maxItems"].get<std::size_t>(), n));
    if (s.contains("items"))
      for (std::size_t i = 0; i < n; ++i) check(value[i], s["items"], fmt::format("{}[{}]", path, i), file, solver);
  }
  if (value.is_object()) {
    static const json kEmpty = json::object();
    const json& props = s.contains("properties") ? s["properties"] : kEmpty;
    std::vector<std::string> allowed;
    for (auto it = props.begin(); it != props.end(); ++it) allowed.push_back(it.key());
    for (auto it = value.begin(); it != value.end(); ++it) {
      const std::string key = it.key();
      const std::string sub = join_path(path, key);
      if (props.contains(key)) {
        const json& prop = props[key];
        if (prop.contains("replaced_by"))
          throw InputError(file + ": " + sub,
                           fmt::format("is no longer read: use '{}' instead ({})",
                                       prop["replaced_by"].get<std::string>(), prop["how"].get<std::string>()));
        if (!read_by(prop, solver)) {
          const std::string other = prop["solvers"][0].get<std::string>();
          throw InputError(file + ": " + sub,
                           fmt::format("is read only by the {} solver, but this scene's solver.type is \"{}\" (remove "
                                       "the key, or set solver.type to \"{}\")",
                                       solver_title(other), solver, other));
        }
        check(it.value(), prop, sub, file, solver);
      } else if (s.contains("additionalProperties") && s["additionalProperties"].is_object()) {
        check(it.value(), s["additionalProperties"], sub, file, solver);
      } else if (s.contains("properties") ||
                 (s.contains("additionalProperties") && s["additionalProperties"] == false)) {
        const std::string near = closest_match(key, allowed);
        throw InputError(file + ": " + sub,
                         fmt::format("unknown key{}; allowed keys here: {}",
                                     near.empty() ? "" : "; did you mean '" + near + "'?", fmt::join(allowed, ", ")));
      }
    }
    // After unknown keys: a misspelt key is reported as such, not as the key it should have been.
    if (s.contains("required"))
      for (const json& r : s["required"])
        if (!value.contains(r.get<std::string>())) fail(fmt::format("missing required key '{}'", r.get<std::string>()));
    if (s.contains("minProperties") && value.size() < s["minProperties"].get<std::size_t>())
      fail(fmt::format("needs at least {} entr{}", s["minProperties"].get<std::size_t>(),
                       s["minProperties"].get<std::size_t>() == 1 ? "y" : "ies"));
    for (auto it = props.begin(); it != props.end(); ++it) {
      if (value.contains(it.key())) continue;
      const json& ps = it.value();
      if (!read_by(ps, solver)) continue;  // the other solver's key: not part of this scene
      const json* def = ps.contains("default") ? &ps["default"] : nullptr;
      if (!def) {
        const json& r = resolve(ps);
        if (r.contains("default")) def = &r["default"];
      }
      if (def) {
        value[it.key()] = *def;
        check(value[it.key()], ps, join_path(path, it.key()), file, solver);
      }
    }
  }
}

// ---- documentation -----------------------------------------------------------

namespace {

struct DocWriter {
  const SchemaValidator& v;
  std::string out;

  std::string type_name(const json& s_in) const {
    if (s_in.contains("$ref")) {
      const std::string ref = s_in["$ref"].get<std::string>();
      const std::string name = ref.substr(ref.rfind('/') + 1);
      if (name == "vec3") return "[x, y, z]";
      if (name == "schedule") return "[[t, value], ...]";
      return "[" + name + "](#" + name + ")";
    }
    if (s_in.contains("oneOf")) {
      std::vector<std::string> parts;
      for (const json& a : s_in["oneOf"]) parts.push_back(type_name(a));
      return fmt::format("{}", fmt::join(parts, " or "));
    }
    if (s_in.contains("const")) return "\"" + s_in["const"].get<std::string>() + "\"";
    if (s_in.contains("enum")) {
      std::vector<std::string> parts;
      for (const json& e : s_in["enum"]) parts.push_back(e.dump());
      return fmt::format("{}", fmt::join(parts, " \\| "));
    }
    std::string t;
    if (s_in.contains("type")) {
      if (s_in["type"].is_string())
        t = s_in["type"].get<std::string>();
      else {
        std::vector<std::string> ts;
        for (const json& x : s_in["type"]) ts.push_back(x.get<std::string>());
        t = fmt::format("{}", fmt::join(ts, " or "));
      }
    }
    if (t == "array" && s_in.contains("items")) return "array of " + type_name(s_in["items"]);
    if (t == "object" && s_in.contains("additionalProperties") && s_in["additionalProperties"].is_object())
      return "map of name → " + type_name(s_in["additionalProperties"]);
    return t;
  }

  static std::string range(const json& s) {
    std::vector<std::string> r;
    if (s.contains("minimum")) r.push_back("≥ " + format_number(s["minimum"].get<double>()));
    if (s.contains("exclusiveMinimum")) r.push_back("> " + format_number(s["exclusiveMinimum"].get<double>()));
    if (s.contains("maximum")) r.push_back("≤ " + format_number(s["maximum"].get<double>()));
    if (s.contains("exclusiveMaximum")) r.push_back("< " + format_number(s["exclusiveMaximum"].get<double>()));
    if (s.contains("oneOf"))
      for (const json& a : s["oneOf"]) {
        const std::string sub = range(a);
        if (!sub.empty()) r.push_back(sub);
      }
    return fmt::format("{}", fmt::join(r, ", "));
  }

  void table(const json& s) {
    if (!s.contains("properties")) return;
    std::vector<std::string> required;
    if (s.contains("required"))
      for (const json& r : s["required"]) required.push_back(r.get<std::string>());
    out += "| key | type | unit | range | default | description |\n|---|---|---|---|---|---|\n";
    for (auto it = s["properties"].begin(); it != s["properties"].end(); ++it) {
      const json& p = it.value();
      if (p.contains("replaced_by")) continue;
      const json& r = v.schema().is_null() ? p : p;
      std::string def = p.contains("default") ? "`" + p["default"].dump() + "`" : "";
      if (std::find(required.begin(), required.end(), it.key()) != required.end()) def = "required";
      std::string desc = p.value("description", std::string());
      if (p.contains("solvers")) {
        for (const char* prefix : {"MPM only: ", "SPH only: ", "MPM: ", "SPH: "})
          if (desc.rfind(prefix, 0) == 0) desc = desc.substr(std::string(prefix).size());
        desc =
            "**" + solver_title(p["solvers"][0].get<std::string>()) + " only** (refused by the other solver). " + desc;
      }
      out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", it.key(), type_name(r), p.value("unit", std::string()),
                         range(p), def, desc);
    }
    out += "\n";
  }
};

}  // namespace

std::string SchemaValidator::markdown_reference() const {
  DocWriter w{*this, {}};
  w.out += "# Scene reference\n\n";
  w.out += "Generated by `bakesim schema --markdown` from `schema/scene.schema.json`; do not edit by hand.\n";
  w.out += "A test fails when this file and the schema disagree.\n\n";
  w.out += schema_.value("description", std::string()) + "\n\n";
  w.out += "## Top level\n\n";
  w.table(schema_);
  for (auto it = schema_["properties"].begin(); it != schema_["properties"].end(); ++it) {
    const json& p = it.value();
    if (p.contains("properties")) {
      w.out += "## `" + it.key() + "`\n\n";
      if (p.contains("description")) w.out += p["description"].get<std::string>() + "\n\n";
      w.table(p);
    }
  }
  for (auto it = schema_["definitions"].begin(); it != schema_["definitions"].end(); ++it) {
    const json& d = it.value();
    if (it.key() == "vec3" || it.key() == "schedule") continue;
    w.out += "## " + it.key() + "\n\n";
    if (d.contains("description")) w.out += d["description"].get<std::string>() + "\n\n";
    if (d.contains("oneOf")) {
      for (const json& a : d["oneOf"]) {
        const json& r = resolve(a);
        std::string key;
        for (auto pit = r["properties"].begin(); pit != r["properties"].end(); ++pit)
          if (pit.value().contains("const")) key = pit.key();
        w.out += "### " + key + " `" + r["properties"][key]["const"].get<std::string>() + "`\n\n";
        w.table(r);
      }
    } else {
      w.table(d);
      for (auto pit = d["properties"].begin(); pit != d["properties"].end(); ++pit)
        if (pit.value().contains("properties")) {
          w.out += "### `" + it.key() + "." + pit.key() + "`\n\n";
          if (pit.value().contains("description")) w.out += pit.value()["description"].get<std::string>() + "\n\n";
          w.table(pit.value());
        }
    }
  }
  return w.out;
}

const SchemaValidator& scene_schema() {
  static const SchemaValidator validator(json::parse(kSceneSchemaText));
  return validator;
}

}  // namespace bakesim

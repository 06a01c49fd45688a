#pragma once
// Validation of JSON documents against the subset of JSON Schema (draft-07)
// that the scene schema uses: type, properties, required,
// additionalProperties, default, enum, const, minimum/maximum (exclusive
// too), minItems/maxItems, minLength, pattern, minProperties, items, oneOf,
// local $ref, plus "unit" for messages and docs. Missing keys with a default
// are filled in, so the validated document is the resolved scene.
#include <nlohmann/json.hpp>
#include <string>

namespace bakesim {

class SchemaValidator {
 public:
  explicit SchemaValidator(nlohmann::json schema);
  // Validates `doc` in place (filling defaults). Throws InputError whose
  // location is "FILE: key.path" and whose message says what is allowed.
  // Properties tagged "solvers": [...] are read only by those solvers: in a
  // scene whose solver.type is another they are refused with a message that
  // names the solver that reads them, and their defaults are not filled in.
  // Properties tagged "replaced_by" are refused with a message naming the new key.
  void validate(nlohmann::json& doc, const std::string& file) const;
  const nlohmann::json& schema() const { return schema_; }
  // The scene reference in Markdown, generated from the schema.
  std::string markdown_reference() const;

 private:
  const nlohmann::json& resolve(const nlohmann::json& s) const;
  void check(nlohmann::json& value, const nlohmann::json& schema, const std::string& path, const std::string& file,
             const std::string& solver) const;
  nlohmann::json schema_;
};

// The scene schema compiled into the binary (schema/scene.schema.json).
const SchemaValidator& scene_schema();

// InputError(where, ...) when `value` nests more than `levels` arrays and
// objects deep. Walks without recursion: it guards the code that copies or
// merges a document before the schema sees it (copying recurses, and a
// value nested 100,000 deep overflowed the stack under AddressSanitizer).
void require_nesting_within(const nlohmann::json& value, int levels, const std::string& where);
inline constexpr int kMaxSceneNesting = 200;  // real scenes nest under 20

// Closest candidate by edit distance, or "" when none is reasonably close.
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace bakesim

#include "exchange/summary_schema.hpp"

#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

namespace compaction::server {

extern const char* const summary_schema_json;  // generated from schema/summary.schema.json

namespace {

// Parsed once, on first use (valijson's Schema is neither copied nor moved).
struct Compiled {
  Compiled() {
    const nlohmann::json document = nlohmann::json::parse(summary_schema_json);
    valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
    valijson::adapters::NlohmannJsonAdapter adapter(document);
    parser.populateSchema(adapter, schema);
  }
  valijson::Schema schema;
};

const valijson::Schema& schema() {
  static const Compiled compiled;
  return compiled.schema;
}

// valijson's context ("<root>", "[classification]", "[scores]", "[0]") as a field path.
std::string field_of(const std::vector<std::string>& context) {
  std::string field;
  for (const std::string& part : context) {
    if (part == "<root>" || part.size() < 2) continue;
    const std::string inner = part.substr(1, part.size() - 2);
    const bool index = !inner.empty() && inner.find_first_not_of("0123456789") == std::string::npos;
    if (index) {
      field += "[" + inner + "]";
    } else {
      field += (field.empty() ? "" : ".") + inner;
    }
  }
  return field;
}

}  // namespace

std::optional<SchemaProblem> check_summary_schema(const nlohmann::json& summary) {
  valijson::Validator validator(valijson::Validator::kStrongTypes);
  valijson::ValidationResults results;
  valijson::adapters::NlohmannJsonAdapter target(summary);
  if (validator.validate(schema(), target, &results)) return std::nullopt;
  std::optional<SchemaProblem> deepest;
  std::size_t depth = 0;
  valijson::ValidationResults::Error e;
  while (results.popError(e)) {
    // A missing property is reported at its object: name the property itself.
    static const std::string missing = "Missing required property '";
    if (e.description.rfind(missing, 0) == 0) {
      const std::size_t end = e.description.find('\'', missing.size());
      e.context.push_back("[" + e.description.substr(missing.size(), end - missing.size()) + "]");
    }
    if (!deepest || e.context.size() > depth) {
      deepest = SchemaProblem{field_of(e.context), e.description};
      depth = e.context.size();
    }
  }
  return deepest;
}

}  // namespace compaction::server

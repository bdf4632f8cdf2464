// Rubric -> scenario JSON text, and splicing it into a scenario file.
#include "scenarios/rubric_fragment.hpp"

#include <cmath>
#include <cctype>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

namespace acdr {
namespace {

/// Shortest decimal that reads back as the same double (as JSON writers do).
std::string number(double v) {
  char text[32];
  for (int digits = 4; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v || digits == 17) break;
  }
  return text;
}

/// Calibrated figures are measured values; four significant digits say all they mean.
std::string benchmark(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

std::string quoted(const std::string& s) { return nlohmann::json(s).dump(); }

}  // namespace

std::string rubric_fragment(const Rubric& rubric, int indent) {
  const std::string in0(static_cast<std::size_t>(indent), ' ');
  const std::string in1 = in0 + "  ", in2 = in1 + "  ", in3 = in2 + "  ";
  std::string s = "{\n" + in1 + "\"terms\": [\n";
  for (std::size_t i = 0; i < rubric.terms.size(); ++i) {
    const RubricTerm& t = rubric.terms[i];
    s += in2 + "{\n";
    s += in3 + "\"metric\": " + quoted(t.metric) + ",\n";
    s += in3 + "\"expert_mean\": " + benchmark(t.expert_mean) + ",\n";
    s += in3 + "\"expert_sd\": " + benchmark(t.expert_sd) + ",\n";
    s += in3 + "\"higher_is_better\": " + (t.higher_is_better ? "true" : "false") + ",\n";
    s += in3 + "\"weight\": " + number(t.weight);
    if (t.safety) s += ",\n" + in3 + "\"safety\": true";
    if (t.sd_floor > 0) s += ",\n" + in3 + "\"sd_floor\": " + number(t.sd_floor);
    s += "\n" + in2 + "}" + (i + 1 < rubric.terms.size() ? "," : "") + "\n";
  }
  s += in1 + "],\n" + in1 + "\"gates\": [\n";
  for (std::size_t i = 0; i < rubric.gates.size(); ++i) {
    const SafetyGate& g = rubric.gates[i];
    s += in2 + "{ \"metric\": " + quoted(g.metric) + ", \"max\": " + number(g.max) + " }" +
         (i + 1 < rubric.gates.size() ? "," : "") + "\n";
  }
  s += in1 + "],\n";
  if (rubric.task) {
    s += in1 + "\"task\": { \"metric\": " + quoted(rubric.task->metric) +
         ", \"min\": " + benchmark(rubric.task->min) + " },\n";
  }
  s += in1 + "\"pass_score\": " + number(rubric.pass_score) + ",\n";
  s += in1 + "\"consecutive_passes_to_master\": " +
       std::to_string(rubric.consecutive_passes_to_master) + "\n";
  s += in0 + "}";
  return s;
}

bool replace_rubric(std::string& text, const Rubric& rubric, std::string* error) {
  // Walk the text at object depth 1 (strings skipped) to the key "rubric", then to the end of
  // its value by brace matching.
  int depth = 0;
  std::size_t key_at = std::string::npos, value_begin = std::string::npos;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      const std::size_t start = i;
      for (++i; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\') ++i;
      }
      if (depth == 1 && key_at == std::string::npos &&
          text.compare(start, i - start + 1, "\"rubric\"") == 0) {
        std::size_t j = i + 1;
        while (j < text.size() && std::isspace(static_cast<unsigned char>(text[j]))) ++j;
        if (j < text.size() && text[j] == ':') {
          ++j;
          while (j < text.size() && std::isspace(static_cast<unsigned char>(text[j]))) ++j;
          if (j < text.size() && text[j] == '{') {
            key_at = start;
            value_begin = j;
            i = j;
            ++depth;
          }
        }
      }
      continue;
    }
    if (c == '{' || c == '[') ++depth;
    if (c == '}' || c == ']') {
      --depth;
      if (value_begin != std::string::npos && depth == 1) {
        std::size_t line_start = text.rfind('\n', key_at);
        line_start = line_start == std::string::npos ? 0 : line_start + 1;
        const int indent = static_cast<int>(key_at - line_start);
        text.replace(value_begin, i + 1 - value_begin, rubric_fragment(rubric, indent));
        return true;
      }
    }
  }
  if (error) {
    *error = value_begin == std::string::npos
                 ? "no top-level \"rubric\" object (expected a scenario file with a rubric)"
                 : "the \"rubric\" object is not closed";
  }
  return false;
}

}  // namespace acdr

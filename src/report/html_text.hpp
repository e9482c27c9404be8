// Text for the self-contained pages (report.html, compare.html,
// stability.html): HTML escaping, JSON inside a <script>, a template's marks.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "deflex/report/json.hpp"

// The libraries compiled into deflex (cmake/embed_report.cmake).
namespace deflex::embedded {
const std::string& report_page();
const std::string& three_js();
const std::string& orbit_controls_js();
const std::string& dygraphs_js();
const std::string& dygraphs_css();
}  // namespace deflex::embedded

namespace deflex::report::detail {

// & < > " as entities.
std::string escape_html(const std::string& s);
// j as compact JSON safe inside <script>: "</" written "<\/" (the same string to JSON).
std::string script_json(const Json& j);
// The page with each mark (in order, each once) replaced by its text; a
// missing mark is an internal error.
std::string fill(const std::string& page, const std::vector<std::pair<std::string, std::string>>& marks);

}  // namespace deflex::report::detail

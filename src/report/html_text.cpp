// Text for the self-contained pages (html_text.hpp).
#include "html_text.hpp"

#include "deflex/diag/diagnostics.hpp"

namespace deflex::report::detail {

std::string escape_html(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string script_json(const Json& j) {
  std::string json = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  // Inside <script>: "</" never appears outside a JSON string, and "<\/" reads the same in one.
  for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 3)) json.insert(at + 1, "\\");
  return json;
}

std::string fill(const std::string& page, const std::vector<std::pair<std::string, std::string>>& marks) {
  std::string out;
  std::size_t pos = 0;
  for (const auto& [mark, text] : marks) {
    const std::size_t at = page.find(mark, pos);
    if (at == std::string::npos) throw Error(ErrorKind::internal, "report template: no mark " + mark);
    out.append(page, pos, at - pos);
    out += text;
    pos = at + mark.size();
  }
  out.append(page, pos, std::string::npos);
  return out;
}

}  // namespace deflex::report::detail

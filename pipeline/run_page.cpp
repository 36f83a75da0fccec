#include "pipeline/run_page.h"

#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"

namespace isoatlas::pipeline {

nlohmann::json stagesJson(const std::vector<RunStage>& stages) {
  nlohmann::json out = nlohmann::json::array();
  for (const RunStage& s : stages) out.push_back({{"name", s.name}, {"status", s.status}, {"detail", s.detail}, {"seconds", s.seconds}});
  return out;
}

nlohmann::json productsJson(const RunProducts& products) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : products.all) out.push_back({{"file", p.file}, {"what", p.what}});
  return out;
}

void writeRunPage(const std::filesystem::path& dir, const std::string& input, const std::vector<RunStage>& stages,
                  const RunProducts& products, double seconds) {
  std::ostringstream html;
  html << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>isoatlas run</title>\n"
       << "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto}td,th{padding:4px 10px;text-align:left}"
       << ".skipped{color:#999}img{max-width:100%}</style></head><body>\n"
       << "<h1>isoatlas run</h1>\n<p>Input: <code>" << input << "</code></p>\n<table>\n"
       << "<tr><th>stage</th><th>status</th><th>seconds</th><th>detail</th></tr>\n";
  char time[32];
  for (const RunStage& s : stages) {
    std::snprintf(time, sizeof time, "%.2f", s.seconds);
    html << "<tr class=\"" << s.status << "\"><td>" << s.name << "</td><td>" << s.status << "</td><td>"
         << (s.status == "done" ? time : "") << "</td><td>" << s.detail << "</td></tr>\n";
  }
  std::snprintf(time, sizeof time, "%.2f", seconds);
  html << "<tr><td><b>total</b></td><td></td><td><b>" << time << "</b></td><td></td></tr>\n";
  html << "</table>\n<h2>Products</h2>\n<ul>\n";
  for (const auto& p : products.all) html << "<li><a href=\"" << p.file << "\">" << p.file << "</a>: " << p.what << "</li>\n";
  html << "</ul>\n";
  for (const auto& p : products.all)
    if (p.picture)
      html << "<figure><img src=\"" << p.file << "\" alt=\"" << p.what << "\"><figcaption>" << p.what
           << "</figcaption></figure>\n";
  html << "<p>Figures: <a href=\"report.json\">report.json</a></p>\n</body></html>\n";
  writeFileAtomically((dir / "index.html").string(), html.str());
}

}  // namespace isoatlas::pipeline

// What `isoatlas run` leaves in its folder besides the products: the record of its stages and
// products, and the page that shows them (index.html), from the same record as report.json's
// "stages" and "products".
#pragma once
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace isoatlas::pipeline {

struct RunStage {
  std::string name, status, detail;  // status: "done" or "skipped"
  double seconds = 0;
};

// The files a run writes into its folder, each named with what it holds; pictures are also shown.
struct RunProducts {
  struct Product {
    std::string file, what;
    bool picture;
  };
  std::filesystem::path dir;
  std::vector<Product> all;
  // Records `file` and returns its path in the folder, to write to.
  std::string add(const std::string& file, const std::string& what, bool picture = false) {
    all.push_back({file, what, picture});
    return (dir / file).string();
  }
};

// report.json's "stages" and "products".
nlohmann::json stagesJson(const std::vector<RunStage>& stages);
nlohmann::json productsJson(const RunProducts& products);

// dir/index.html: the input, the stages with their seconds and the total, the products, the pictures.
void writeRunPage(const std::filesystem::path& dir, const std::string& input, const std::vector<RunStage>& stages,
                  const RunProducts& products, double seconds);

}  // namespace isoatlas::pipeline

// The paper's Figure 4 as one picture: labelled panels side by side, each tone-mapped like the PNG.
#pragma once
#include "image/image.h"
#include <string>
#include <vector>

namespace bp {

struct SheetPanel {
  std::string label;
  const ImageRGB* image;  // null: an empty panel that says the layer is not available
};

// Panels in rows of `columns`, each the size of the first available image, labelled underneath.
// Written atomically as PNG; throws std::runtime_error naming the file on failure.
void write_contact_sheet(const std::string& path, const std::vector<SheetPanel>& panels, float exposure_stops = 0.0f,
                         int columns = 3);

}  // namespace bp

// The checkpoint key (--checkpoint, --resume): everything that shapes the image, canonically, so a
// resume continues only under the same; and what --ratio auto and --eye-direct auto read back from it.
#pragma once
#include "passes/combined.h"
#include "render/render_spec.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bp {

// eye_direct: what the eye vertex's direct light is (shared or pt; --eye-direct auto resolved).
std::string options_key(const RenderSpec& o, int width, int height, float patch_size, std::uint32_t bins,
                        const std::optional<RoundShape>& shape, const std::string& eye_direct);

// A walkthrough's views in the key (empty for a plain render, whose --camera options_key names):
// ";views=N:HASH", HASH of every view's camera, so a resume with other views is refused.
std::string views_key(const RenderSpec& o, const std::vector<SceneCamera>& views);

// The round a checkpoint was saved with (its key's ";round=Nspp+Mit"), for --ratio auto's --resume.
std::optional<RoundShape> round_of_key(const std::string& key);

// The eye-direct choice a checkpoint was saved with (its key's ";eye_direct=shared|pt"), for
// --eye-direct auto's --resume.
std::optional<bool> eye_direct_shared_of_key(const std::string& key);

}  // namespace bp

// A walkthrough's frames as a video (--video): the PNGs encoded by ffmpeg, run as a program.
#pragma once
#include <string>

namespace bp {

// Whether an executable `ffmpeg` is on PATH.
bool ffmpeg_on_path();

// Encodes the PNGs that `pattern` names (printf style, "out/walk_%04d.png", from 0) at `fps` frames
// per second into `video` (H.264, yuv420p; the size rounded down to even). Throws std::runtime_error
// when ffmpeg cannot be started or fails.
void encode_png_sequence(const std::string& pattern, double fps, const std::string& video);

}  // namespace bp

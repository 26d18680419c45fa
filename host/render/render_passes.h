// The passes of a render: the round and its weights, the devices opened with the scene, PT and RB
// built on them, and --ratio auto's probe and --eye-direct auto's choice made before the first
// counted sample.
#pragma once
#include "render/render_job.h"
#include "render/render_state.h"

namespace bp {

// The round shape and the weights both passes use; --ratio 0 (no PT samples) runs RB unweighted.
void choose_round(RenderState& s);

// The devices --device names (render_devices.h), each with the scene; the light tree's receivers
// must fit each of them (else UsageError).
void open_devices(RenderState& s);

// PT on each PT device and RB on its device, each adding into the render's accumulators (one
// device) or its own (several).
void build_passes(RenderState& s);

// --ratio auto: the probe picks c (or a resumed render takes the checkpoint's); --eye-direct auto:
// pt where point, spot and sun lights hold kEyeDirectPtFromDeltaLightShare of the light, else shared
// below kEyeDirectSharedBelowSpp PT samples per pixel, or what a resumed render was saved with.
// Both passes get the chosen c's weights. Reads s.resumed; notes the choices.
void choose_auto_settings(RenderState& s, RenderObserver& observer);

}  // namespace bp

#!/usr/bin/env python3
"""Issue #13: should RB give the sun a ray bundle of its own (one more transfer per iteration along
the sun's direction, which lights every patch in front) instead of per-patch shadow rays? Python
standard library only; renders with bundlepath (--mode combined --ratio 1, where RB samples lights).

  sun_bundle.py SCENE.glb [--width W] [--height H] [--iterations N] [--patch-size M]...
                [--eye-direct pt|shared]... [--out DIR] [--bundlepath PATH]
                (N: PT samples per pixel and RB iterations alike)

A sun bundle changes two things at once, measured apart here:
  * what is sampled: every patch gets the sun in every iteration, where now its one light sample
    chooses the sun with the light tree's share. That is --rb-sun own, which takes the sun's own
    sample with a shadow ray; the weights then count it (kernels/shared/weights.h,
    delta_light_weights). Measured: each image's variance and time, chosen against own.
  * how visibility is found: a transfer along the sun instead of one shadow ray per patch. Its
    estimate is the same (the lit fraction of the patch; the bundle's bins average a few points of it
    where the ray takes one, which matters only on patches a shadow edge crosses), its cost is one
    transfer per iteration -- emit, scans, scatter, resolve and gather, their device time per
    iteration in the same render -- against the own samples' shadow rays (the rise of rb_outgoing's
    device time per iteration from chosen to own).
  Times are chosen's render time plus N times the extra per iteration (the own rays, or a transfer):
  differences of device times of the same kernels, which a busy machine disturbs less than it does
  two renders' wall times. "own, by a bundle" has own's variance.
Also shown, as what any sampling of the sun apart could reach: "split", the sum of the variances of
two independent renders of the scene with its directional lights alone and with the others alone
(each light sampled on its own, in PT too).
Variance per pixel and channel as docs/design.md §7: (a - b)^2 / 2 / (R^2 + 0.01) between seeds 1 and 2,
R the mean of the scene's two chosen renders; the pt and rb parts from the pt.* and rb.* layers.
Efficiency: 1 / (variance x time), relative to chosen.
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rb_regions import read_exr, read_glb, write_glb  # noqa: E402

TRANSFER_KERNELS = ('rb_emit', 'scan_chunk_totals', 'scan_totals', 'scan_chunks', 'rb_tile_scatter',
                    'rb_tile_resolve', 'rb_gather')


def light_variant(src, dst, keep_directional):
    """A copy of SRC with only its directional lights (keep_directional) or only the others."""
    gltf, rest = read_glb(src)
    lights = gltf['extensions']['KHR_lights_punctual']['lights']
    for node in gltf['nodes']:
        ext = node.get('extensions', {}).get('KHR_lights_punctual')
        if ext is not None and (lights[ext['light']]['type'] == 'directional') != keep_directional:
            del node['extensions']['KHR_lights_punctual']
    write_glb(dst, gltf, rest)


def render(args, scene, prefix, seed, patch_size, eye_direct, rb_sun):
    cmd = [args.bundlepath, 'render', scene, '--mode', 'combined', '--ratio', '1', '--spp', str(args.iterations),
           '--width', str(args.width), '--height', str(args.height), '--seed', str(seed), '--patch-size',
           str(patch_size), '--eye-direct', eye_direct, '--rb-sun', rb_sun, '--out', prefix, '--stats',
           prefix + '.json']
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return read_exr(prefix + '.exr')[2], json.load(open(prefix + '.json'))


def variance(pair, reference_pair, layer):
    """docs/design.md §7's relative variance of one render, from two seeds, against the reference pair's mean."""
    total, n = 0.0, 0
    for c in 'RGB':
        r1, r2 = reference_pair[0][c], reference_pair[1][c]
        a, b = pair[0][layer + c], pair[1][layer + c]
        for i in range(len(a)):
            r = 0.5 * (r1[i] + r2[i])
            total += (a[i] - b[i]) ** 2 / 2.0 / (r * r + 0.01)
            n += 1
    return total / n


def per_iteration(stats, kernels):
    launches = stats['launches']
    return sum(launches[k]['device_seconds'] / launches[k]['count'] for k in kernels if k in launches)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('scene')
    ap.add_argument('--width', type=int, default=640)
    ap.add_argument('--height', type=int, default=360)
    ap.add_argument('--iterations', type=int, default=128)
    ap.add_argument('--patch-size', type=float, action='append')
    ap.add_argument('--eye-direct', action='append', choices=('pt', 'shared'))
    ap.add_argument('--out', default='build/sun-bundle')
    ap.add_argument('--bundlepath', default=os.environ.get('BUNDLEPATH', 'build/bundlepath'))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    variants = {}
    for name, keep in (('sun', True), ('rest', False)):
        variants[name] = os.path.join(args.out, name + '.glb')
        light_variant(args.scene, variants[name], keep)
    print('| patch size | patches | eye direct | sampling | variance (pt + rb) | time (s) | efficiency |')
    print('|---|---|---|---|---|---|---|')
    for patch_size in args.patch_size or [0.31]:
        for eye_direct in args.eye_direct or ['pt']:
            runs = {}  # (label, scene) -> ([image seed 1, image seed 2], [stats...])
            for label, scene, rb_sun in (('chosen', args.scene, 'chosen'), ('own', args.scene, 'own'),
                                         ('sun', variants['sun'], 'chosen'), ('rest', variants['rest'], 'chosen')):
                pairs = [render(args, scene, os.path.join(args.out, f'{label}-{patch_size}-{eye_direct}-s{seed}'),
                                seed, patch_size, eye_direct, rb_sun) for seed in (1, 2)]
                runs[label] = ([p[0] for p in pairs], [p[1] for p in pairs])
            reference = runs['chosen'][0]
            var = {label: {layer: variance(images, reference, layer) for layer in ('', 'pt.', 'rb.')}
                   for label, (images, _) in runs.items()}
            seconds = {label: 0.5 * sum(s['render_seconds'] for s in stats) for label, (_, stats) in runs.items()}
            t_transfer = per_iteration(runs['chosen'][1][0], TRANSFER_KERNELS)
            t_own_rays = (per_iteration(runs['own'][1][0], ('rb_outgoing',)) -
                          per_iteration(runs['chosen'][1][0], ('rb_outgoing',)))
            rows = [('chosen (now)', var['chosen'], seconds['chosen']),
                    ('own, by shadow rays', var['own'], seconds['chosen'] + args.iterations * t_own_rays),
                    ('own, by a bundle', var['own'], seconds['chosen'] + args.iterations * t_transfer),
                    ('split (each light apart)', {k: var['sun'][k] + var['rest'][k] for k in var['sun']}, None)]
            base = var['chosen'][''] * seconds['chosen']
            patches = runs['chosen'][1][0]['patches']
            for label, v, t in rows:
                efficiency = f'{base / (v[""] * t):.2f}' if t else ''
                print(f"| {patch_size} | {patches} | {eye_direct} | {label} | {v['']:.4g} ({v['pt.']:.3g} + "
                      f"{v['rb.']:.3g}) | {f'{t:.2f}' if t else ''} | {efficiency} |")
            print(f'| | | | per iteration: a transfer {1e3 * t_transfer:.2f} ms, the own samples\' shadow rays '
                  f'{1e3 * t_own_rays:.2f} ms | | | |')
            sys.stdout.flush()


if __name__ == '__main__':
    main()

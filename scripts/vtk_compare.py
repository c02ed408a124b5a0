#!/usr/bin/env python3
"""Times VTK's two volume ray casters against `splatlab render` on the same volume, TF and camera.

Not part of the build or the tests: it needs Debian's python3-vtk9 and an X display (run it under
xvfb-run). Each round renders VTK's GL ray caster, SplatLab and VTK's CPU ray caster one after the
other, so a drifting machine falls on all three alike. Every figure is the median of --frames frames
after one warm-up frame; the images are written beside each other for a look.

The VTK side is set up to do the work SplatLab does: every pixel is cast (image sample distance 1,
no automatic coarsening), rays sample the trilinear field every --sample-distance voxels, no shading,
and the TF means the same thing: SplatLab's opacity is extinction per voxel length (times --density),
so VTK's scalar opacity per voxel length is 1 - exp(-opacity * density).
"""
import argparse
import gzip
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

try:
    import vtk
except ImportError:
    sys.exit("vtk_compare: needs VTK's Python bindings: apt-get install python3-vtk9 (not a SplatLab dependency)")


def read_nhdr(path):
    """The volume of a detached-header NRRD (raw or gzip), as vtkImageData: the form ../shared uses."""
    fields = {}
    with open(path) as f:
        for line in f:
            if ":" in line and not line.startswith("#"):
                key, value = line.split(":", 1)
                fields[key.strip()] = value.strip()
    for key in ("sizes", "type", "encoding", "data file"):
        if key not in fields:
            sys.exit(f"vtk_compare: {path}: no '{key}' field")
    types = {"uint8": (1, "SetDataScalarTypeToUnsignedChar"), "unsigned char": (1, "SetDataScalarTypeToUnsignedChar"),
             "uchar": (1, "SetDataScalarTypeToUnsignedChar"), "int16": (2, "SetDataScalarTypeToShort"),
             "short": (2, "SetDataScalarTypeToShort"), "uint16": (2, "SetDataScalarTypeToUnsignedShort"),
             "ushort": (2, "SetDataScalarTypeToUnsignedShort"), "float": (4, "SetDataScalarTypeToFloat")}
    if fields["type"] not in types:
        sys.exit(f"vtk_compare: {path}: type '{fields['type']}', expected one of {', '.join(types)}")
    size, setType = types[fields["type"]]
    dims = [int(v) for v in fields["sizes"].split()]
    spacing = [float(v) for v in fields.get("spacings", "1 1 1").split()]
    dataPath = os.path.join(os.path.dirname(path), fields["data file"])
    opener = gzip.open if fields["encoding"] in ("gz", "gzip") else open
    with opener(dataPath, "rb") as f:
        data = f.read()
    if len(data) != dims[0] * dims[1] * dims[2] * size:
        sys.exit(f"vtk_compare: {dataPath}: {len(data)} bytes, expected {dims[0] * dims[1] * dims[2] * size}")
    if size > 1 and fields.get("endian", "little") != sys.byteorder:
        sys.exit(f"vtk_compare: {path}: endian '{fields.get('endian')}', expected this machine's ({sys.byteorder})")
    importer = vtk.vtkImageImport()
    importer.CopyImportVoidPointer(data, len(data))
    getattr(importer, setType)()
    importer.SetNumberOfScalarComponents(1)
    importer.SetWholeExtent(0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    importer.SetDataExtentToWholeExtent()
    importer.SetDataSpacing(*spacing)
    importer.Update()
    image = vtk.vtkImageData()
    image.DeepCopy(importer.GetOutput())
    return image, dims, spacing


def sub(a, b): return [x - y for x, y in zip(a, b)]
def scale(a, s): return [x * s for x in a]
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def normalize(a): return scale(a, 1.0 / math.sqrt(dot(a, a)))


def orbit_camera(azimuth, elevation, distance, dims, spacing, up):
    """Eye, centre and view-up of SplatLab's orbit camera (renderer/src/math/camera.cpp, makeImagePlane)."""
    centre = [0.5 * s * (d - 1) for s, d in zip(spacing, dims)]
    radius = 0.5 * max(math.sqrt(sum((s * (d - 1)) ** 2 for s, d in zip(spacing, dims))), math.sqrt(dot(spacing, spacing)))
    up = normalize(up)
    ref = [1.0, 0.0, 0.0] if abs(up[0]) < 0.9 else [0.0, 1.0, 0.0]
    e1 = normalize(sub(ref, scale(up, dot(ref, up))))
    e2 = cross(up, e1)
    az, el = math.radians(azimuth), math.radians(max(-89.9, min(89.9, elevation)))
    to_eye = [math.cos(el) * (math.cos(az) * a + math.sin(az) * b) + math.sin(el) * u for a, b, u in zip(e1, e2, up)]
    forward = scale(to_eye, -1.0)
    right = normalize(cross(forward, up))
    down = cross(forward, right)
    eye = [c + t * distance * radius for c, t in zip(centre, to_eye)]
    return eye, centre, scale(down, -1.0)   # VTK's image y grows upwards


def tf_points(args):
    """The TF's colour and opacity points (`splatlab tf` reads a preset name or a JSON file as --tf does)."""
    result = subprocess.run([args.splatlab, "tf", args.tf], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"vtk_compare: --tf {args.tf}: {result.stderr.strip()}")
    return json.loads(result.stdout)


def tf_functions(tf, lo, hi, density):
    """VTK's colour and opacity functions of the TF: values are the window's fractions ("window fraction")
    or data units ("data"); SplatLab's opacity is extinction per voxel length."""
    colour, opacity = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
    at = (lambda v: v) if tf.get("units") == "data" else (lambda v: lo + v * (hi - lo))
    for p in tf["colour"]:
        colour.AddRGBPoint(at(p["value"]), *p["rgb"])
    for p in tf["opacity"]:
        opacity.AddPoint(at(p["value"]), 1.0 - math.exp(-p["opacity"] * density))
    return colour, opacity


def vtk_renderer(kind, image, dims, spacing, args):
    lo, hi = image.GetScalarRange()
    colour, opacity = tf_functions(args.tf_points, lo, hi, args.density)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(sum(spacing) / 3.0)   # SplatLab's "voxel length": the mean spacing
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    mapper = vtk.vtkOpenGLGPUVolumeRayCastMapper() if kind == "gl" else vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputData(image)
    mapper.SetAutoAdjustSampleDistances(0)
    mapper.SetSampleDistance(args.sample_distance * min(spacing))
    if kind == "cpu":
        mapper.SetImageSampleDistance(1.0)
        mapper.SetInteractiveSampleDistance(args.sample_distance * min(spacing))
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    ren = vtk.vtkRenderer()
    ren.AddVolume(volume)
    ren.SetBackground(0, 0, 0)
    az, el, dist, fov = args.camera
    eye, centre, view_up = orbit_camera(az, el, dist, dims, spacing, args.up)
    cam = ren.GetActiveCamera()
    cam.SetPosition(*eye)
    cam.SetFocalPoint(*centre)
    cam.SetViewUp(*view_up)
    cam.SetViewAngle(fov)
    ren.ResetCameraClippingRange()
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(args.size, args.size)
    win.AddRenderer(ren)
    return win


def time_vtk(win, frames):
    times = []
    for i in range(frames + 1):          # the first frame uploads the volume and compiles: not counted
        start = time.perf_counter()
        win.Render()
        win.WaitForCompletion()
        if i: times.append(1e3 * (time.perf_counter() - start))
    return statistics.median(times)


def save_vtk(win, path):
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()


def run_splatlab(args, out_path, frames, extra=()):
    cmd = [args.splatlab, "render", args.volume, "--tf", args.tf, "--size", f"{args.size}x{args.size}",
           "--camera", ",".join(str(v) for v in args.camera), "--up", args.up_name, "--density", str(args.density),
           "--compositing", "sheet-front-to-back", "--filter", args.filter, "--opaque-alpha", str(args.opaque_alpha),
           "--frames", str(frames), "--out", out_path, *extra]
    return cmd, subprocess.run(cmd, capture_output=True, text=True)


def time_splatlab(args, out_path):
    cmd, result = run_splatlab(args, out_path, args.frames)
    found = re.search(r"([0-9.]+) ms/frame \(median", result.stdout)
    if result.returncode != 0 or not found:
        sys.exit(f"vtk_compare: {' '.join(cmd)} failed:\n{result.stdout}{result.stderr}")
    renderer = re.search(r" on (.*)$", result.stdout.strip().splitlines()[-1])
    return float(found.group(1)), renderer.group(1) if renderer else "?"


def agreement(args, windows):
    """PSNR of SplatLab's images against VTK's GL ray caster (both 8-bit PNG over black): the object-aligned
    pre-classified sheets and the image-aligned post-classified slabs (CPU), which classify as VTK does."""
    vtk_png = os.path.join(args.images, "vtk_gl.png")
    windows["gl"].Render()
    save_vtk(windows["gl"], vtk_png)
    variants = [("pre-classified sheets (GL)", "splatlab.png", ()),
                (f"post-classified slabs {args.slabs:g} voxels (CPU)", "splatlab_post.png",
                 ("--image-slabs", str(args.slabs), "--post-classify"))]
    print("| SplatLab | PSNR against VTK's GL ray caster |\n|---|---|")
    for what, name, extra in variants:
        out = os.path.join(args.images, name)
        cmd, result = run_splatlab(args, out, 1, extra)
        if result.returncode != 0:
            sys.exit(f"vtk_compare: {' '.join(cmd)} failed:\n{result.stdout}{result.stderr}")
        compared = subprocess.run([args.splatlab, "compare", out, vtk_png], capture_output=True, text=True)
        found = re.search(r"PSNR ([0-9.inf]+) dB", compared.stdout)
        print(f"| {what} | {found.group(1) if found else compared.stdout + compared.stderr} dB |", flush=True)
    print(f"images: {args.images}/splatlab.png, splatlab_post.png, vtk_gl.png")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("volume", nargs="?", help="a .nhdr volume (default: bonsai.nhdr in --data)")
    parser.add_argument("--data", default=os.environ.get("SPLATLAB_DATA_DIR"), help="folder of the shared volumes (default: $SPLATLAB_DATA_DIR)")
    parser.add_argument("--tf", default=os.path.join(ROOT, "assets", "presets", "bonsai.json"),
                        help="a preset name (`splatlab tf` lists them) or a JSON file")
    parser.add_argument("--splatlab", default=os.path.join(ROOT, "build", "release", "app", "splatlab"))
    parser.add_argument("--size", type=int, default=512, help="square image side in pixels")
    parser.add_argument("--camera", default="30,20,2.5,30", help="azimuth,elevation,distance,fov as `splatlab render` takes it")
    parser.add_argument("--up", default="z", help="x, y, z, -x, -y or -z (a minus sign needs --up=-z)")
    parser.add_argument("--density", type=float, default=1.0)
    parser.add_argument("--filter", default="ewa", help="SplatLab's filter: ewa, adaptive, reconstruction, low-pass")
    parser.add_argument("--opaque-alpha", type=float, default=0.998,
                        help="SplatLab's early termination (its default 0.998); VTK's CPU ray caster ends a ray at 1 - 255/32767 = 0.9922")
    parser.add_argument("--sample-distance", type=float, default=1.0, help="VTK's ray step in voxels (of the smallest spacing)")
    parser.add_argument("--frames", type=int, default=5)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--images", default="vtk_compare", help="folder for the three images of the last round")
    parser.add_argument("--agreement", action="store_true",
                        help="no timing: the PSNR of SplatLab's pre-classified sheets and post-classified slabs "
                             "against VTK's GL ray caster")
    parser.add_argument("--slabs", type=float, default=0.25, help="with --agreement: the slabs' thickness in voxels")
    args = parser.parse_args()

    if args.volume is None:
        if not args.data:
            sys.exit("vtk_compare: no volume: give a .nhdr, or --data / SPLATLAB_DATA_DIR with bonsai.nhdr")
        args.volume = os.path.join(args.data, "bonsai.nhdr")
    for path, what in ((args.volume, "volume"), (args.splatlab, "splatlab binary (build first)")):
        if not os.path.isfile(path):
            sys.exit(f"vtk_compare: {path}: no such file, expected the {what}")
    args.tf_points = tf_points(args)
    try:
        camera = [float(v) for v in args.camera.split(",")]
    except ValueError:
        camera = []
    if len(camera) != 4:
        sys.exit(f"vtk_compare: --camera '{args.camera}': expected azimuth,elevation,distance,fov (numbers)")
    args.camera = camera
    axes = {"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1]}
    name = args.up.lstrip("+-")
    if name not in axes:
        sys.exit(f"vtk_compare: --up '{args.up}': expected x, y, z, -x, -y or -z")
    args.up_name, args.up = args.up, scale(axes[name], -1.0 if args.up.startswith("-") else 1.0)
    os.makedirs(args.images, exist_ok=True)

    image, dims, spacing = read_nhdr(args.volume)
    windows = {kind: vtk_renderer(kind, image, dims, spacing, args) for kind in ("gl", "cpu")}
    if args.agreement:
        return agreement(args, windows)
    print(f"{os.path.basename(args.volume)} {dims[0]}x{dims[1]}x{dims[2]}, {args.size}x{args.size}, camera "
          f"{','.join(f'{v:g}' for v in args.camera)}, VTK {vtk.vtkVersion.GetVTKVersion()} (ray step "
          f"{args.sample_distance:g} voxel), SplatLab {args.filter} sheets front to back (opaque at "
          f"{args.opaque_alpha:g}); median of {args.frames} frames")
    print("| round | VTK GL ray caster | SplatLab | VTK CPU ray caster | SplatLab vs GL | CPU vs SplatLab |")
    print("|---|---|---|---|---|---|")
    for r in range(args.rounds):
        gl = time_vtk(windows["gl"], args.frames)
        ours, gl_renderer = time_splatlab(args, os.path.join(args.images, "splatlab.png"))
        cpu = time_vtk(windows["cpu"], args.frames)
        print(f"| {r + 1} | {gl:.1f} ms | {ours:.1f} ms | {cpu:.1f} ms | {gl / ours:.2f}x faster | "
              f"{'CPU' if cpu < ours else 'SplatLab'} {max(cpu, ours) / min(cpu, ours):.2f}x faster |", flush=True)
    for kind, win in windows.items():
        save_vtk(win, os.path.join(args.images, f"vtk_{kind}.png"))
    found = re.search(r"OpenGL renderer string: *(.*)", windows["gl"].ReportCapabilities())
    print(f"SplatLab on {gl_renderer}; VTK's GL ray caster on {found.group(1).strip() if found else '?'}")
    print(f"images: {args.images}/splatlab.png, vtk_gl.png, vtk_cpu.png")


if __name__ == "__main__":
    main()

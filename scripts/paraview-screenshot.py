# Renders one frame of `ricochet dem impact|campaign --vtk DIR` with ParaView, as docs/paraview.md
# shows: grains as spheres of their radius coloured by speed, the block's spheres in grey, seen
# along the slab's thin axis (y). The frame is the one where the block is lowest (maximum
# penetration) unless a step is given.
#   xvfb-run -a -s "-screen 0 1600x900x24" pvbatch scripts/paraview-screenshot.py DIR OUT.png [STEP]
# (Debian packages paraview, python3-paraview and xvfb; not needed to build or test Ricochet.)
import glob
import os
import re
import sys

from paraview.simple import (Calculator, ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, Glyph, LegacyVTKReader, Render, SaveScreenshot, Show)


def step_of(path):
    return int(re.search(r"_(\d+)\.vtk$", path).group(1))


def lowest_block_step(folder):
    best = None
    for path in glob.glob(os.path.join(folder, "block_[0-9]*.vtk")):
        with open(path) as f:
            text = f.read()
        head, rest = text.split("\nPOINTS ", 1)
        n = int(rest.split()[0])
        values = rest.split("\n", 1)[1].split()[: 3 * n]
        z = min(float(values[3 * i + 2]) for i in range(n))
        if best is None or z < best[0]:
            best = (z, step_of(path))
    return best[1]


folder, out = sys.argv[1], sys.argv[2]
step = int(sys.argv[3]) if len(sys.argv) > 3 else lowest_block_step(folder)
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1400, 520]
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
view.OrientationAxesVisibility = 0

grains = LegacyVTKReader(FileNames=[os.path.join(folder, f"grains_{step}.vtk")])
speed = Calculator(Input=grains, ResultArrayName="speed", Function="mag(v)")
balls = Glyph(Input=speed, GlyphType="Sphere")
balls.ScaleArray = ["POINTS", "radius"]
balls.ScaleFactor = 2.0
balls.GlyphMode = "All Points"
shown = Show(balls, view)
ColorBy(shown, ("POINTS", "speed"))
lut = GetColorTransferFunction("speed")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.RescaleTransferFunction(0.0, 1.5)
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(lut, view)
bar.Title = "grain speed [m/s]"
bar.ComponentTitle = ""
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]
bar.RangeLabelFormat = "%-#.1f"

block = LegacyVTKReader(FileNames=[os.path.join(folder, f"block_{step}.vtk")])
spheres = Glyph(Input=block, GlyphType="Sphere")
spheres.ScaleArray = ["POINTS", "radius"]
spheres.ScaleFactor = 2.0
spheres.GlyphMode = "All Points"
sb = Show(spheres, view)
sb.ColorArrayName = ["POINTS", ""]
sb.DiffuseColor = [0.55, 0.55, 0.55]
sb.AmbientColor = [0.55, 0.55, 0.55]

# Side view along -y, centred on the block, a third of a metre across.
view.ResetCamera()
info = block.GetDataInformation().GetBounds()
cx, cz = 0.5 * (info[0] + info[1]), info[4]
view.CameraViewUp = [0, 0, 1]
view.CameraFocalPoint = [cx, 0.0, cz]
view.CameraPosition = [cx, -2.0, cz]
view.CameraParallelProjection = 1
view.CameraParallelScale = 0.09
Render(view)
SaveScreenshot(out, view, ImageResolution=[1400, 520])
print(f"wrote {out} (step {step})")

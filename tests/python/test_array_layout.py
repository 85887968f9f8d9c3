"""The module's arrays are (rows, columns, channels) with row 0 at the top, checked against what the
built-in Cornell box shows where (an independent value: the scene's own layout), on an image whose height,
width and channel count all differ, and against the EXR the program writes for the same render."""
import numpy as np


def test_rows_columns_and_channels_are_where_the_scene_puts_them(sym, cli, tmp_path):
    width, height = 48, 30
    img, stats = sym.render("cornell", spp=16, width=width, height=height, threads=2, progress=False)
    assert img.shape == (height, width, 3) and img.dtype == np.float32
    assert img.flags["C_CONTIGUOUS"]
    red = (img[:, :, 0] > 2 * img[:, :, 1]) & (img[:, :, 0] > 0.05)
    green = (img[:, :, 1] > 2 * img[:, :, 0]) & (img[:, :, 1] > 0.05)
    assert red.sum() > 20 and green.sum() > 20
    red_x, green_x = np.nonzero(red)[1].mean(), np.nonzero(green)[1].mean()
    assert red_x < width / 2 < green_x, f"the red wall on the left, the green on the right: columns {red_x:.1f}, {green_x:.1f}"
    lum = img @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
    top_row = int(np.unravel_index(np.argmax(lum), lum.shape)[0])
    assert top_row < height // 6, f"the light is at the top of the image (row {top_row} of {height})"
    cli("render", "-W", width, "-H", height, "-s", 16, "-t", 2, "-o", tmp_path / "x.exr")
    assert np.array_equal(sym.read_image(str(tmp_path / "x.exr")), img)

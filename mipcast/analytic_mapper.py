"""Analytic MIP: the exact maximum of the trilinear interpolant, cell by cell."""
from __future__ import annotations

from .max_blocks import block_maxima_image
from .mip_mapper import MIPVolumeMapper
from .object_state import object_state
from .validation import check_image


class AnalyticMIPVolumeMapper(MIPVolumeMapper):
    """Exact MIP on the GPU: no samples to miss, no sample distance to choose.

    Each ray walks the cells it crosses (a 3D DDA over voxel planes); in
    every cell the trilinear interpolant along the ray is a cubic, built
    exactly from the cell's 8 corner values (``texelFetch``, so the GPU's
    low-precision filter weights play no part), and its maximum is taken at
    the segment ends and the derivative's roots (see METHODS.md §2 and
    ``shaders/amip_cell.glsl``).  Cells whose largest corner cannot beat the
    running maximum are skipped.  The sample distance setting is ignored.
    Colour and opacity come from the volume property exactly as in stock MIP;
    interpolation is always trilinear.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = AnalyticMIPVolumeMapper()
    >>> mapper.SetInputData(make_fixture("vessels", size=32))
    >>> volume = vtkVolume()
    >>> mapper.Attach(volume)
    >>> mapper.IsAttached()
    True
    """

    PIECES = ("mip_globals", "amip_cell", "amip_loop", "no_stock_sample", "mip_color")

    #: Cells per edge of a skipping block (the coarse level is 1/BLOCK^3 the size).
    BLOCK = 4
    #: Voxels between the exact lower-bound samples taken before the cell walk.
    BOUND_STRIDE = 4.0

    def _push_uniforms(self, uniforms) -> None:
        image = self.GetInput()
        dims = image.GetDimensions() if image is not None else (2, 2, 2)
        uniforms.SetUniform3f("u_mc_dims", [float(n) for n in dims])
        uniforms.SetUniformf("u_mc_blockSize", float(self.BLOCK))

        uniforms.SetUniformf("u_mc_boundStride", float(self.BOUND_STRIDE))
        if image is not None and image.GetNumberOfPoints() > 0:
            self._update_block_maxima(image)

    def _update_block_maxima(self, image) -> None:
        """(Re)build the block-maximum level when the input changed; it rides in the mask slot."""
        state = object_state(self)
        stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime())
        if state.get("blocks_of") == stamp:
            return
        low, high = image.GetPointData().GetScalars().GetRange(0)
        self.SetMaskInput(block_maxima_image(check_image(image), self.BLOCK, low, high))
        self.SetMaskTypeToBinary()
        state["blocks_of"] = stamp

"""What the GPU allows: the 3D texture limit, free GPU memory, the textures each method uploads.

Three questions a mapper asks before it draws a large volume:

* the largest 3D texture, points per axis (:func:`max_texture_size_3d`:
  ``GL_MAX_3D_TEXTURE_SIZE`` through ``vtkTextureObject``);
* free GPU memory, where the driver says (:func:`free_gpu_memory`:
  ``GL_NVX_gpu_memory_info`` on NVIDIA, ``GL_ATI_meminfo`` on AMD; ``None``
  elsewhere, e.g. Mesa llvmpipe or Intel, where OpenGL has no such query);
* how many bytes of texture the volume costs (:func:`volume_texture_bytes`;
  each mapper's ``GetTextureBytes()`` adds what its method uploads besides).

Both driver queries need a window that has rendered once (a current OpenGL
context); before that they answer 0 / ``None`` (unknown).  See
docs/reliability.md, section "GPU limits and memory".
"""
from __future__ import annotations

from typing import Optional

#: ``GL_MAX_3D_TEXTURE_SIZE``.
GL_MAX_3D_TEXTURE_SIZE = 0x8073
#: ``GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX`` (kilobytes).
GL_NVX_CURRENT_AVAILABLE_VIDMEM = 0x9049
#: ``GL_TEXTURE_FREE_MEMORY_ATI`` (four ints, the first: free kilobytes of the texture pool).
GL_ATI_TEXTURE_FREE_MEMORY = 0x87FC

#: Bytes per component VTK's ray caster uploads for each scalar type: 8/16-bit
#: integers as they are, everything else (32-bit integers, float, double) as float32.
_UPLOAD_BYTES = {"char": 1, "signed char": 1, "unsigned char": 1, "short": 2, "unsigned short": 2}


def _ready(window) -> bool:
    return window is not None and hasattr(window, "GetState") and not window.GetNeverRendered()


def max_texture_size_3d(window) -> int:
    """``GL_MAX_3D_TEXTURE_SIZE`` of ``window`` (points per axis), 0 if it has not rendered yet.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> max_texture_size_3d(vtkRenderWindow())   # never rendered: unknown
    0
    """
    return _texture_limit(window, "GetMaximumTextureSize3D")


def max_picture_size(window) -> int:
    """The largest picture ``window``'s driver draws, pixels a side (``GL_MAX_TEXTURE_SIZE``: VTK's
    offscreen framebuffer is made of such textures; larger, it draws black), 0 if it has not rendered yet.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> max_picture_size(vtkRenderWindow())   # never rendered: unknown
    0
    """
    return _texture_limit(window, "GetMaximumTextureSize")


def _texture_limit(window, query: str) -> int:
    """``vtkTextureObject.<query>(window)``, 0 while the window has not rendered (no context to ask)."""
    if not _ready(window):
        return 0
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

    return int(getattr(vtkTextureObject, query)(window))


def gl_extensions(window) -> frozenset:
    """The OpenGL extensions ``window``'s context reports (empty if it has not rendered)."""
    if not _ready(window):
        return frozenset()
    cached = getattr(window, "_mipcast_extensions", None)  # Python attribute on the wrapper: per object
    if cached is None:
        report = window.ReportCapabilities() or ""
        cached = frozenset(word for word in report.split() if word.startswith("GL_"))
        try:
            window._mipcast_extensions = cached
        except AttributeError:
            pass
    return cached


def free_gpu_memory(window) -> Optional[int]:
    """Free GPU memory in bytes as the driver reports it, or ``None`` when it cannot say.

    Asked through ``GL_NVX_gpu_memory_info`` (NVIDIA) or ``GL_ATI_meminfo``
    (AMD, the texture pool) only when the context lists the extension; Mesa's
    software renderer, Intel and Apple drivers list neither, so the answer
    there is ``None`` (unknown), never a guess.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> free_gpu_memory(vtkRenderWindow()) is None   # never rendered: unknown
    True
    """
    extensions = gl_extensions(window)
    if not extensions:
        return None
    for name, enum in (("GL_NVX_gpu_memory_info", GL_NVX_CURRENT_AVAILABLE_VIDMEM),
                       ("GL_ATI_meminfo", GL_ATI_TEXTURE_FREE_MEMORY)):
        if name in extensions:
            window.MakeCurrent()
            values = [0, 0, 0, 0]
            window.GetState().vtkglGetIntegerv(enum, values)
            if values[0] > 0:
                return int(values[0]) * 1024
    return None


def volume_texture_bytes(image, components: Optional[int] = None) -> int:
    """Bytes of the 3D texture VTK uploads for ``image``'s point scalars.

    Points times components times the uploaded component size (8/16-bit
    integers keep their size, other types go up as float32).  ``components``
    overrides the scalars' own count (analytic MIP's packed copy has 4).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=16)
    >>> image.GetPointData().GetScalars().GetDataTypeAsString(), volume_texture_bytes(image)
    ('float', 16384)
    >>> volume_texture_bytes(image, components=4)
    65536
    """
    if image is None:
        return 0
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        return 0
    count = scalars.GetNumberOfComponents() if components is None else int(components)
    size = _UPLOAD_BYTES.get(scalars.GetDataTypeAsString(), 4)
    return int(image.GetNumberOfPoints()) * count * size


def describe(window) -> dict:
    """The limits of ``window`` as a dictionary (for reports): texture limit and free memory.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> describe(vtkRenderWindow())
    {'max_texture_size_3d': 0, 'free_gpu_memory': None}
    """
    return {"max_texture_size_3d": max_texture_size_3d(window), "free_gpu_memory": free_gpu_memory(window)}


def window_of(volume):
    """The render window drawing ``volume`` (the first renderer that holds it), or ``None``."""
    for index in range(volume.GetNumberOfConsumers() if volume is not None else 0):
        window = getattr(volume.GetConsumer(index), "GetRenderWindow", lambda: None)()
        if window is not None:
            return window
    return None

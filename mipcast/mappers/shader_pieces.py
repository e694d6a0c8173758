"""Load mipcast's GLSL pieces and install them on a volume's shader property.

Every piece is one file in ``mipcast/shaders`` (``shaders/`` in the source
tree) whose header names the VTK template tag it fills and how::

    // mipcast piece: sampled_loop
    // fills: Shading::Init
    // mode: replace

``replace`` swaps VTK's code at the tag for the piece; ``augment`` keeps VTK's
code and appends the piece after it.  Tags are checked against
:data:`TEMPLATE_TAGS`, and a piece may not contain VTK's tag marker itself
(VTK would substitute it again).  User values never enter the source: numbers
reach the shader through custom uniforms only.

Sampled methods share one ray loop, the ``sampled_loop`` piece, whose hooks
(:data:`SAMPLED_HOOKS`: before the loop, at each sample, after the loop) one
*hook piece* per method fills at :data:`HOOK_TAG`; the hook contract is
documented at the top of ``shaders/sampled_loop.glsl``.  A new sampled
projection is one hook piece plus the generic pieces
(:func:`mipcast.mappers.mip.sampled_projection_mapper`); pieces outside the
package load from folders added with :func:`register_folder`.
"""
from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Iterable, Optional

#: Tags of VTK's ``Rendering/VolumeOpenGL2/shaders/raycasterfs.glsl``, taken
#: from the template compiled into VTK 9.7.2 and ParaView 5.11's VTK 9.2
#: (identical in both).
TEMPLATE_TAGS = frozenset("""
Base::Dec Base::Exit Base::Impl Base::Init BinaryMask::Dec BinaryMask::Impl
CallWorker::Impl Clipping::Dec Clipping::Exit Clipping::Impl Clipping::Init
CompositeMask::Dec CompositeMask::Impl ComputeColor::Dec ComputeColor::Unif
ComputeDensityGradient::Dec ComputeGradient::Dec ComputeGradientOpacity1D::Dec
ComputeLighting::Dec ComputeOpacity::Dec ComputeRGBA2DWithGradient::Dec
ComputeRayDirection::Dec ComputeVolumetricShadow::Dec Cropping::Dec
Cropping::Exit Cropping::Impl Cropping::Init CustomUniforms::Dec DepthPass::Exit
DepthPass::Impl DepthPass::Init DepthPeeling::Dec DepthPeeling::Ray::Init
DepthPeeling::Ray::PathCheck GradientCache::Dec Matrices::Init Output::Dec
PhaseFunction::Dec Picking::Dec Picking::Exit PreComputeGradients::Impl
RenderToImage::Dec RenderToImage::Exit RenderToImage::Impl RenderToImage::Init
Shading::Dec Shading::Exit Shading::Impl Shading::Init System::Dec
Terminate::Exit Terminate::Impl Terminate::Init Termination::Dec Transfer2D::Dec
""".split())

#: The one sampled ray loop (``shaders/sampled_loop.glsl``).
SAMPLED_LOOP = "sampled_loop"
#: The tag a sampled method's hook piece fills: global scope, after VTK's
#: ``computeColor``/``computeOpacity`` and mipcast's helpers, before castRay().
HOOK_TAG = "Picking::Dec"
#: The functions a hook piece defines for ``sampled_loop`` (name: signature).
SAMPLED_HOOKS = {
    "mcBeginRay": "void mcBeginRay(inout int first, inout int count)",
    "mcSample": "bool mcSample(float value, int i)",
    "mcEndRay": "void mcEndRay(int count)",
}
#: What a hook piece that skips blocks (``#define MC_SAMPLE_BLOCKS``) defines besides.
SAMPLED_BLOCK_HOOKS = {"mcBlockSkips": "bool mcBlockSkips(float blockBound)"}

#: The exact projections' cell helpers (``shaders/amip_cell.glsl``), whose cell
#: hooks one hook piece per exact projection defines at :data:`HOOK_TAG`
#: (``amip_max_hooks``, ``amip_min_hooks``, ``amip_average_hooks``).
CELL_HELPERS = "amip_cell"
#: The functions a cell-hook piece defines for ``amip_cell`` (name: signature).
CELL_HOOKS = {
    "mcCellsBegin": "float mcCellsBegin()",
    "mcCellsGoOn": "bool mcCellsGoOn(float value)",
    "mcCell": "void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)",
    "mcCellsEnd": "float mcCellsEnd(float value)",
}
#: The cell walk that skips blocks (``shaders/amip_loop_blocks.glsl``), and what its hook piece defines besides.
CELL_BLOCKS_LOOP = "amip_loop_blocks"
CELL_BLOCK_HOOKS = {"mcCellsBlockSkips": "bool mcCellsBlockSkips(float blockBound, float value)"}

#: Folders searched, in order, after the package's own ``shaders`` folder
#: (see :func:`register_folder`).
PIECE_FOLDERS: list = []

MARKER = "// mipcast piece: "
VTK_TAG_PREFIX = "//VTK::"
_HEADER = re.compile(
    r"\A// mipcast piece: (?P<name>\w+)\n// fills: (?P<tag>[\w:]+)\n// mode: (?P<mode>\w+)\n")


@dataclass(frozen=True)
class Piece:
    """One GLSL piece: the template tag it fills and the text put there."""

    name: str
    tag: str
    mode: str
    text: str

    @property
    def vtk_tag(self) -> str:
        """The tag as it appears in VTK's template, e.g. ``//VTK::Shading::Init``."""
        return VTK_TAG_PREFIX + self.tag

    @property
    def replacement(self) -> str:
        """The text handed to ``AddFragmentShaderReplacement``."""
        if self.mode == "augment":
            return f"{self.vtk_tag}\n{self.text}"
        return self.text


def register_folder(path) -> Path:
    """Let :func:`load_piece` find pieces in the folder ``path`` too (after the package's).

    Returns the folder as a :class:`~pathlib.Path`.  Registering a folder twice
    is harmless.

    Examples
    --------
    >>> import tempfile
    >>> folder = register_folder(tempfile.mkdtemp())
    >>> folder in PIECE_FOLDERS
    True
    >>> unregister_folder(folder)
    """
    folder = Path(path)
    if not folder.is_dir():
        raise ValueError(f"no folder {str(folder)!r} to load shader pieces from")
    if folder not in PIECE_FOLDERS:
        PIECE_FOLDERS.append(folder)
    load_piece.cache_clear()
    return folder


def unregister_folder(path) -> None:
    """Undo :func:`register_folder` (a folder not registered is ignored)."""
    folder = Path(path)
    if folder in PIECE_FOLDERS:
        PIECE_FOLDERS.remove(folder)
    load_piece.cache_clear()


def _read_piece_text(name: str) -> str:
    try:
        return resources.files("mipcast.shaders").joinpath(f"{name}.glsl").read_text()
    except FileNotFoundError:
        pass
    for folder in PIECE_FOLDERS:
        path = folder / f"{name}.glsl"
        if path.is_file():
            return path.read_text()
    where = ", ".join(["mipcast/shaders"] + [str(folder) for folder in PIECE_FOLDERS])
    raise ValueError(f"no shader piece named {name!r} in {where}")


@functools.lru_cache(maxsize=None)
def load_piece(name: str) -> Piece:
    """Read and check one piece from the package's ``shaders`` folder or a registered one.

    Parameters
    ----------
    name : str
        File name without ``.glsl``; the package's ``shaders`` folder is
        searched first, then :data:`PIECE_FOLDERS` in order.

    Returns
    -------
    Piece

    Examples
    --------
    >>> load_piece("mip_color").tag
    'Shading::Exit'
    """
    if not isinstance(name, str) or not re.fullmatch(r"\w{1,200}", name):
        shown = repr(name) if len(repr(name)) <= 80 else repr(name)[:77] + "..."
        raise ValueError(f"shader piece names are file names without .glsl (word characters, at most 200), "
                         f"not {shown}")
    return parse_piece(name, _read_piece_text(name))


def check_hooks(piece: Piece, hooks: Optional[dict] = None) -> Piece:
    """Check that ``piece`` is a hook piece for ``sampled_loop`` (or defines ``hooks``); return it.

    It must fill :data:`HOOK_TAG` and define every function of ``hooks``
    (default :data:`SAMPLED_HOOKS`; :data:`CELL_HOOKS` for the cell walk's
    hook pieces); a sampled hook piece that skips blocks (``#define
    MC_SAMPLE_BLOCKS``) also :data:`SAMPLED_BLOCK_HOOKS`.  ``ValueError``
    names what is missing.

    Examples
    --------
    >>> check_hooks(load_piece("mip_hooks")).name
    'mip_hooks'
    >>> check_hooks(load_piece("amip_min_hooks"), CELL_HOOKS).name
    'amip_min_hooks'
    """
    sampled = hooks is None or hooks is SAMPLED_HOOKS
    hooks = SAMPLED_HOOKS if hooks is None else hooks
    loop = "sampled loop" if sampled else "cell walk"
    if piece.tag != HOOK_TAG:
        raise ValueError(
            f"shader piece {piece.name!r} fills {piece.tag}, but the {loop}'s hook "
            f"piece must fill {HOOK_TAG}")
    code = re.sub(r"//[^\n]*", "", piece.text)
    if sampled and re.search(r"#define\s+MC_SAMPLE_BLOCKS\b", code):
        hooks = {**hooks, **SAMPLED_BLOCK_HOOKS}
    missing = [signature for name, signature in hooks.items()
               if not re.search(rf"\b{signature.split()[0]}\s+{name}\s*\(", code)]
    if missing:
        where = "shaders/sampled_loop.glsl" if sampled else "shaders/amip_cell.glsl, shaders/amip_loop_blocks.glsl"
        raise ValueError(
            f"shader piece {piece.name!r} does not define the {loop}'s hook(s) "
            f"{'; '.join(missing)} (see {where})")
    return piece


def parse_piece(name: str, text: str) -> Piece:
    """Check a piece's header and body; raise ``ValueError`` naming the fault.

    Examples
    --------
    >>> parse_piece("p", "// mipcast piece: p\\n// fills: Base::Dec\\n// mode: augment\\nfloat x;\\n").mode
    'augment'
    """
    header = _HEADER.match(text)
    if header is None:
        raise ValueError(
            f"shader piece {name!r} must start with the three header lines "
            "'// mipcast piece: NAME', '// fills: TAG', '// mode: replace|augment'")
    if header["name"] != name:
        raise ValueError(f"shader piece file {name!r} declares the name {header['name']!r}")
    if header["tag"] not in TEMPLATE_TAGS:
        raise ValueError(
            f"shader piece {name!r} fills unknown tag {header['tag']!r}; "
            "it must be one of VTK raycasterfs.glsl's tags (see TEMPLATE_TAGS)")
    if header["mode"] not in ("replace", "augment"):
        raise ValueError(f"shader piece {name!r} has mode {header['mode']!r}; use replace or augment")
    if VTK_TAG_PREFIX in text:
        raise ValueError(
            f"shader piece {name!r} contains {VTK_TAG_PREFIX!r}: VTK would substitute it "
            "again; write tags without that prefix in comments")
    return Piece(header["name"], header["tag"], header["mode"], text)


def install(shader_property, pieces: Iterable[Piece]) -> None:
    """Put ``pieces`` on a volume's shader property, replacing earlier mipcast pieces.

    Refuses (``ValueError``) two pieces for one tag, and a tag that already
    carries a replacement that is not mipcast's (someone else's code would be
    silently lost), and the ``sampled_loop`` (``amip_cell``) piece without a
    hook piece that defines its hooks (:func:`check_hooks`).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> volume = vtkVolume()
    >>> install(volume.GetShaderProperty(), [load_piece("mip_color")])
    >>> installed_tags(volume.GetShaderProperty())
    ['//VTK::Shading::Exit']
    """
    pieces = list(pieces)
    for loop, hooks, kind in ((SAMPLED_LOOP, SAMPLED_HOOKS, "hook piece"),
                              (CELL_HELPERS, CELL_HOOKS, "cell-hook piece")):
        if any(piece.name == loop for piece in pieces):
            found = [piece for piece in pieces if piece.tag == HOOK_TAG]
            if not found:
                raise ValueError(
                    f"the {loop} piece needs a {kind} filling {HOOK_TAG} "
                    f"(defining {', '.join(hooks)}); none is among the pieces")
            blocks = loop == CELL_HELPERS and any(piece.name == CELL_BLOCKS_LOOP for piece in pieces)
            check_hooks(found[0], {**hooks, **CELL_BLOCK_HOOKS} if blocks else hooks)
    claimed: dict = {}
    for piece in pieces:
        if piece.vtk_tag in claimed:
            raise ValueError(
                f"shader pieces {claimed[piece.vtk_tag]!r} and {piece.name!r} both fill "
                f"{piece.tag}; a slot takes one piece")
        claimed[piece.vtk_tag] = piece.name
    uninstall(shader_property)
    foreign = {tag for tag, text in _fragment_replacements(shader_property) if MARKER not in text}
    clashes = sorted(foreign & set(claimed))
    if clashes:
        raise ValueError(
            f"the volume's shader property already has replacements for {', '.join(clashes)} "
            "that mipcast did not install; remove them (ClearFragmentShaderReplacement) or "
            "use a separate vtkVolume")
    for piece in pieces:
        shader_property.AddFragmentShaderReplacement(piece.vtk_tag, True, piece.replacement, False)


def uninstall(shader_property) -> None:
    """Remove every mipcast piece from a shader property, leaving others alone.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> prop = vtkVolume().GetShaderProperty()
    >>> install(prop, [load_piece("mip_color")])
    >>> uninstall(prop)
    >>> installed_tags(prop)
    []
    """
    for tag, text in _fragment_replacements(shader_property):
        if MARKER in text:
            shader_property.ClearFragmentShaderReplacement(tag, True)


def installed_tags(shader_property) -> list:
    """Tags that currently carry a mipcast piece, sorted.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> prop = vtkVolume().GetShaderProperty()
    >>> install(prop, [load_piece("mip_globals"), load_piece("mip_color")])
    >>> installed_tags(prop)
    ['//VTK::Base::Dec', '//VTK::Shading::Exit']
    """
    return sorted(tag for tag, text in _fragment_replacements(shader_property) if MARKER in text)


def _fragment_replacements(shader_property) -> list:
    from vtkmodules.vtkCommonCore import reference

    found = []
    for index in range(shader_property.GetNumberOfShaderReplacements()):
        if shader_property.GetNthShaderReplacementTypeAsString(index) != "Fragment":
            continue
        tag, first, text, every = reference(""), reference(False), reference(""), reference(False)
        shader_property.GetNthShaderReplacement(index, tag, first, text, every)
        found.append((str(tag), str(text)))
    return found

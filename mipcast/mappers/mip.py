"""The base mipcast mapper: VTK's GPU ray caster running mipcast's own ray loop."""
from __future__ import annotations

from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow, vtkWeakReference
from vtkmodules.vtkRenderingCore import vtkVolume
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.core import parameter_tables
from mipcast.core.object_state import object_state
from mipcast.core.parameters import defaults, parameter_accessors, uniform_values
from mipcast.mappers import shader_pieces
from mipcast.mappers.stereo import eye_uniforms
from mipcast.core.validation import check_image


#: The piece every mipcast mapper adds to its own: stereo-correct ray directions.
STEREO_PIECE = "stereo_ray_direction"


@parameter_accessors
class MIPVolumeMapper(vtkOpenGLGPUVolumeRayCastMapper):
    """Sampled maximum intensity projection through mipcast's shader pieces.

    A drop-in for ``vtkGPUVolumeRayCastMapper`` in MIP mode: input, sample
    distance, auto-adjust, image sample distance, the volume property's
    transfer functions and interpolation, and the image's spacing, origin and
    direction matrix all behave as they do there, with the same samples as
    stock VTK (sample ``i`` at ``entry + i * step``) in a faster, counted loop.
    VTK keeps shader code on the ``vtkVolume``, so the mapper must be attached
    to its volume with :meth:`Attach` (which also calls ``volume.SetMapper``).
    Rendering an unattached mipcast mapper, or one whose input is unusable (see
    :func:`mipcast.core.validation.check_image`), reports a VTK error naming the
    problem and draws nothing.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = MIPVolumeMapper()
    >>> mapper.SetInputData(make_fixture("vessels", size=32))
    >>> volume = vtkVolume()
    >>> mapper.Attach(volume)
    >>> volume.GetMapper() is mapper
    True

    See docs/methods.md, section MIP: ``docs/methods.md#mip``.
    """

    #: Shader pieces this method installs (file names in ``shaders/``):
    #: ``sampled_loop`` is the one sampled ray loop, ``mip_hooks`` fills its
    #: hooks (see :func:`sampled_projection_mapper` for other projections).
    PIECES = ("mip_globals", "refusal", "sampled_loop", "mip_hooks", "no_stock_sample", "mip_color")
    #: The method's parameter table (:mod:`mipcast.core.parameter_tables`):
    #: subclasses get a ``SetX``/``GetX`` per entry (:func:`parameter_accessors`).
    PARAMETERS = parameter_tables.MIP

    def __init__(self) -> None:
        super().__init__()
        self.SetBlendModeToMaximumIntensity()
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _check_before_render)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _restore_after_refused_render)

    # -- attachment ---------------------------------------------------------
    def Attach(self, volume: vtkVolume) -> None:
        """Install this method's shader pieces on ``volume`` and set its mapper.

        Parameters
        ----------
        volume : vtkVolume
            The volume to render.  Its shader property receives mipcast's
            pieces; replacements other code put on the same tags are refused.
        """
        if not isinstance(volume, vtkVolume):
            raise TypeError(f"Attach needs a vtkVolume, got {type(volume).__name__}")
        previous = self.GetAttachedVolume()
        if previous is not None and previous is not volume:
            self.Detach()
        self._install_pieces(volume)
        volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniformf("u_mc_refused", 0.0)
        link = vtkWeakReference()  # a C++ weak pointer: Python wrappers come and go
        link.Set(volume)
        object_state(self)["volume"] = link
        volume.SetMapper(self)
        self._push_uniforms(volume.GetShaderProperty().GetFragmentCustomUniforms())
        self.Modified()

    def GetShaderPieces(self) -> tuple:
        """Names of the shader pieces (files in ``shaders/``) the mapper needs now.

        :data:`PIECES`, plus ``float_readout`` while
        :func:`mipcast.mappers.float_readout.render_float` renders (which also swaps
        ``refusal`` for ``image_terminate``: VTK's render-to-image reads the
        scene depth at the wrong pixels in renderers that do not start at
        the window's corner).  Subclasses whose
        pieces depend on their settings override this; the pieces are
        re-installed at the next render when the answer changes.
        """
        return self._with_readout(self.PIECES)

    def _with_readout(self, names) -> tuple:
        """``names``, adapted for a float readout while one renders (else unchanged)."""
        if not object_state(self).get("exact_readout"):
            return tuple(names)
        # rendering to image: VTK's ray set-up with the viewport-offset fix (it also refuses)
        return tuple("image_terminate" if n == "refusal" else n for n in names) + ("float_readout",)

    def _install_pieces(self, volume) -> None:
        names = self._pieces_now(volume)
        shader_pieces.install(volume.GetShaderProperty(), [shader_pieces.load_piece(n) for n in names])
        object_state(self)["installed"] = names

    def _pieces_now(self, volume) -> tuple:
        """:meth:`GetShaderPieces`, plus the stereo piece while an eye of a stereo pair renders."""
        names = tuple(self.GetShaderPieces())
        return names + (STEREO_PIECE,) if eye_uniforms(self, volume) is not None else names

    def Detach(self) -> None:
        """Remove mipcast's pieces from the attached volume (if any)."""
        volume = self.GetAttachedVolume()
        if volume is not None:
            shader_pieces.uninstall(volume.GetShaderProperty())
        object_state(self).pop("volume", None)

    def NeedsRefinement(self) -> bool:
        """Whether a timer should render again to refine the picture (False: this method draws it at once).

        The foveated mapper with progressive refinement answers True while
        refining (:mod:`mipcast.mappers.refinement` drives it).
        """
        return False

    def GetAttachedVolume(self):
        """The volume given to :meth:`Attach`, or ``None``."""
        link = object_state(self).get("volume")
        return None if link is None else link.Get()

    def GetRenderProblem(self):
        """Why this mapper would refuse to render now, or ``None`` if it can.

        Checked at the start of every render: the mapper must be attached
        (:meth:`Attach`) and its input must pass
        :func:`mipcast.core.validation.check_image` (checked once per input
        modification).
        """
        if not self.IsAttached():
            return ("rendered without Attach(volume): its shader pieces are not on the "
                    "volume, so nothing is drawn. Call mapper.Attach(volume) instead of "
                    "volume.SetMapper(mapper).")
        if self.GetNumberOfInputConnections(0) == 0:
            return "no input: call SetInputData(image) or SetInputConnection(port)"
        self.GetInputAlgorithm().Update()
        image = self.GetInput()
        if image is None:
            return "no input: call SetInputData(image) or SetInputConnection(port)"
        state = object_state(self)
        stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime())
        if state.get("checked_input") != stamp:
            try:
                check_image(image)
            except (TypeError, ValueError) as error:
                return f"input refused, nothing is drawn: {error}"
            state["checked_input"] = stamp
        return None

    # -- parameters (the table's values) ------------------------------------
    def _parameters(self) -> dict:
        state = object_state(self)
        if "parameters" not in state:
            state["parameters"] = defaults(type(self).PARAMETERS)
        return state["parameters"]

    def _get_parameter(self, name: str):
        return self._parameters()[name]

    def _set_parameter(self, name: str, value) -> None:
        """Store a checked value; its uniforms go up at the next render (nothing recompiles)."""
        self._parameters()[name] = value
        self.Modified()

    def _push_uniforms(self, uniforms) -> None:
        """Write this method's custom uniforms (``u_mc_*``); called at Attach and every render.

        The table's uniforms (each parameter's :class:`~mipcast.core.parameters.Uniform`),
        then :meth:`_push_derived_uniforms`.
        """
        settings = dict(self._parameters(), **self._derived_settings())
        for name, (kind, value) in uniform_values(type(self).PARAMETERS, settings).items():
            if kind == "int":
                uniforms.SetUniformi(name, int(value))
            elif kind == "vec3":
                uniforms.SetUniform3f(name, list(value))
            else:
                uniforms.SetUniformf(name, float(value))
        self._push_derived_uniforms(uniforms, settings)

    def _derived_settings(self) -> dict:
        """Values besides the parameters that the table's uniforms depend on (e.g. the window)."""
        return {}

    def _push_derived_uniforms(self, uniforms, settings) -> None:
        """Uniforms that no single parameter drives (the window, readout flags, sizes)."""

    def IsAttached(self) -> bool:
        """True when the attached volume uses this mapper and still carries its pieces."""
        volume = self.GetAttachedVolume()
        if volume is None or volume.GetMapper() is not self:
            return False
        names = object_state(self).get("installed", ())
        wanted = {shader_pieces.load_piece(n).vtk_tag for n in names}
        return wanted <= set(shader_pieces.installed_tags(volume.GetShaderProperty()))


def _check_before_render(mapper, event) -> None:
    """Bring pieces and uniforms up to date; refuse stock shaders or bad input.

    A refusal reports a VTK error naming the problem and draws nothing.
    """
    problem = mapper.GetRenderProblem()
    object_state(mapper)["render_problem"] = problem  # for later observers of the same render
    volume = mapper.GetAttachedVolume()
    if mapper.IsAttached():
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        uniforms.SetUniformf("u_mc_refused", 0.0 if problem is None else 1.0)  # shaders/refusal.glsl
    if problem is None:
        if object_state(mapper).get("installed") != mapper._pieces_now(volume):
            mapper._install_pieces(volume)
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        mapper._push_uniforms(uniforms)
        eye = eye_uniforms(mapper, volume)
        if eye is not None:  # rays from this eye (shaders/stereo_ray_direction.glsl)
            uniforms.SetUniform3f("u_mc_eyePosObj", eye["u_mc_eyePosObj"])
            uniforms.SetUniform3f("u_mc_eyeDirection", eye["u_mc_eyeDirection"])
            uniforms.SetUniformf("u_mc_eyeParallel", eye["u_mc_eyeParallel"])
        return
    vtkOutputWindow.GetInstance().DisplayErrorText(f"{type(mapper).__name__}: {problem}\n")
    mapper.InvokeEvent(vtkCommand.ErrorEvent)
    # Keep VTK from touching the input at all: with cropping on and an empty
    # cropping box, vtkGPUVolumeRayCastMapper::ValidateRender silently skips
    # the render before it reads the input.  (Letting VTK draw refused input
    # with the refusal piece discarding every fragment is not enough: VTK 9.7
    # itself segfaults when scalars go from one component to three, or
    # vanish, between two renders.)  Restored at VolumeMapperRenderEndEvent.
    object_state(mapper)["refused"] = (mapper.GetCropping(), mapper.GetCroppingRegionPlanes())
    mapper.SetCropping(True)
    mapper.SetCroppingRegionPlanes(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def _restore_after_refused_render(mapper, event) -> None:
    refused = object_state(mapper).pop("refused", None)
    if refused is not None:
        mapper.SetCropping(refused[0])
        mapper.SetCroppingRegionPlanes(*refused[1])


def sampled_projection_mapper(hooks: str, color: str = "mip_color") -> type:
    """A :class:`MIPVolumeMapper` subclass whose sampled loop runs the hook piece ``hooks``.

    A new sampled projection (MinIP, average, ...) is one GLSL piece that fills
    the hooks of the one sampled ray loop (``shaders/sampled_loop.glsl``
    documents them: ``mcBeginRay``, ``mcSample``, ``mcEndRay``) and leaves the
    ray's normalised value in ``mc_rayMax``; everything else (ray set-up,
    refusal, colour through the transfer functions, float readout) is MIP's.
    Pieces outside the package load from folders added with
    :func:`mipcast.mappers.shader_pieces.register_folder`.

    Parameters
    ----------
    hooks : str
        Name of the hook piece (file name without ``.glsl``).
    color : str
        The ``Shading::Exit`` piece that colours ``mc_rayMax``.

    Returns
    -------
    type
        The mapper class; its :data:`~MIPVolumeMapper.PIECES` are MIP's with
        ``mip_hooks`` (and ``mip_color``) swapped.

    Raises
    ------
    ValueError
        The piece is missing, or is not a hook piece defining every hook.

    Examples
    --------
    >>> cls = sampled_projection_mapper("mip_hooks")
    >>> cls.PIECES == MIPVolumeMapper.PIECES
    True
    """
    shader_pieces.check_hooks(shader_pieces.load_piece(hooks))
    shader_pieces.load_piece(color)
    swap = {"mip_hooks": hooks, "mip_color": color}
    return type(f"SampledProjectionMapper_{hooks}", (MIPVolumeMapper,), {
        "__doc__": f"Sampled projection through the hook piece {hooks!r} (see sampled_projection_mapper).",
        "PIECES": tuple(swap.get(name, name) for name in MIPVolumeMapper.PIECES)})

"""Views in patient terms: anterior, posterior, left, right, superior, inferior.

mipcast's world coordinates are DICOM's patient system, LPS (+x towards the
patient's left, +y posterior, +z superior): the readers
(:func:`mipcast.io.read_volume`) place every voxel there through the
image's origin and direction matrix, and the renderers honour the direction
matrix.  So a view in patient terms is a fixed camera direction in world
coordinates, whatever the slices' orientation (axial, coronal, sagittal or
oblique): the image's direction matrix decides which of its index axes
ends up facing the camera.  The labels follow clinical viewers:

========== =================================== ============= ===================
view       camera on the patient's ...,        screen up     screen right
           looking towards
========== =================================== ============= ===================
anterior   front (-y), towards +y              superior (+z) patient's left
posterior  back (+y), towards -y               superior      patient's right
left       left side (+x), towards -x          superior      posterior
right      right side (-x), towards +x         superior      anterior
superior   head end (+z), towards -z           anterior (-y) patient's right
inferior   feet end (-z), towards +z           anterior      patient's left
========== =================================== ============= ===================

(anterior and inferior as radiographs and axial slices are read: the
patient's left on the viewer's right.)  All are parallel projections.

An image with no orientation (identity direction matrix, e.g. a ``.vti``
written without one, or the bundled head CT) is taken as LPS as it stands;
:func:`orientation_code` tells what an image's axes point to.

Examples
--------
>>> sorted(PATIENT_VIEWS)
['anterior', 'inferior', 'left', 'posterior', 'right', 'superior']
>>> PATIENT_VIEWS["anterior"]
((0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
"""
from __future__ import annotations

from typing import Tuple

import numpy as np

#: view -> (direction of projection, view up), both in world LPS coordinates.
PATIENT_VIEWS = {
    "anterior": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "posterior": ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
    "left": ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "right": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "superior": ((0.0, 0.0, -1.0), (0.0, -1.0, 0.0)),
    "inferior": ((0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
}

_LPS_LETTERS = (("R", "L"), ("A", "P"), ("I", "S"))  # (towards -axis, towards +axis)


def set_patient_view(renderer, image, view: str) -> None:
    """Point ``renderer``'s camera at ``image`` from the patient side named by ``view``.

    Parameters
    ----------
    renderer : vtkRenderer
    image : vtkImageData
        Its world bounds (direction matrix included) frame the view.
    view : str
        A key of :data:`PATIENT_VIEWS`.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderer
    >>> from mipcast.data_fixtures import make_fixture
    >>> renderer = vtkRenderer()
    >>> set_patient_view(renderer, make_fixture("spheres", size=16), "anterior")
    >>> [round(v, 3) for v in renderer.GetActiveCamera().GetDirectionOfProjection()]
    [0.0, 1.0, 0.0]
    """
    forward, up = PATIENT_VIEWS[view]
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0.0, 0.0, 0.0)
    camera.SetPosition(*(-np.asarray(forward)))
    camera.SetViewUp(*up)
    camera.SetParallelProjection(True)
    camera.SetViewAngle(30.0)
    renderer.ResetCamera(image.GetBounds())


def orientation_code(image) -> str:
    """Three letters: the patient direction (LPS world) each index axis i, j, k points to most.

    ``"LPS"`` for an identity direction matrix; an axial DICOM series is
    ``"LPS"``, a coronal one e.g. ``"LIP"``.

    Examples
    --------
    >>> from mipcast.data_fixtures.synthetic import image_from_array
    >>> import numpy as np
    >>> orientation_code(image_from_array(np.zeros((2, 2, 2), np.float32),
    ...                                   direction=[[1, 0, 0], [0, 0, 1], [0, -1, 0]]))
    'LIP'
    """
    matrix = np.array([[image.GetDirectionMatrix().GetElement(r, c) for c in range(3)] for r in range(3)])
    letters = []
    for column in matrix.T:
        axis = int(np.argmax(np.abs(column)))
        letters.append(_LPS_LETTERS[axis][int(column[axis] > 0)])
    return "".join(letters)


def view_basis(view: str) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(direction of projection, screen up, screen right) of a patient view, in LPS.

    Examples
    --------
    >>> [float(v) for v in view_basis("anterior")[2]]  # the patient's left on the viewer's right
    [1.0, 0.0, 0.0]
    """
    forward, up = (np.asarray(v, dtype=float) for v in PATIENT_VIEWS[view])
    return forward, up, np.cross(forward, up)

"""Install mipcast: the core package ``mipcast/`` plus the top-level folders.

``filters/`` (pyvista), ``plugin/`` (ParaView), ``shaders/`` (GLSL pieces) and
``data_fixtures/`` (test volumes) live at the top of the repository and are
installed as ``mipcast.filters``, ``mipcast.plugin``, ``mipcast.shaders`` and
``mipcast.data_fixtures`` (``package_dir`` below): import mipcast from the
installed package, not from the checkout.
"""
from setuptools import setup

TOP_LEVEL = {"mipcast.filters": "filters", "mipcast.plugin": "plugin",
             "mipcast.shaders": "shaders", "mipcast.data_fixtures": "data_fixtures"}
CORE = ["mipcast", "mipcast.core", "mipcast.reference", "mipcast.mappers", "mipcast.io",
        "mipcast.bench", "mipcast.app"]

setup(
    name="mipcast",
    version="0.1.0",
    description="Better maximum intensity projection for VTK's GPU ray caster",
    long_description=open("README.md", encoding="utf-8").read(),
    long_description_content_type="text/markdown",
    python_requires=">=3.9",
    packages=CORE + list(TOP_LEVEL),
    package_dir=TOP_LEVEL,
    package_data={"mipcast.shaders": ["*.glsl"], "mipcast.data_fixtures": ["*.md"],
                  "mipcast.plugin": ["*.xml", "*.md", "macros/*.py"]},
    install_requires=[
        "vtk>=9.2",
        "pyvista>=0.48",
        "numpy>=1.24",
        "pydicom>=2.4",
        # DICOM decoders used through pydicom's pixel-data plugins (see docs/dicom.md):
        # JPEG baseline/extended/lossless and JPEG-LS, JPEG 2000 and HTJ2K, fast RLE.
        "pylibjpeg>=2.0",
        "pylibjpeg-libjpeg>=2.1",
        "pylibjpeg-openjpeg>=2.3",
        "pylibjpeg-rle>=2.0",
        # Siemens CSA headers and mosaic geometry (nibabel.nicom)
        "nibabel>=5.0",
        # NRRD: every encoding, detached headers, axes of any kind (VTK's reader misreads 3D Slicer's vector
        # volumes, takes a short first axis as components, and reads only the first of a time series)
        "pynrrd>=1.0",
        # TIFF stacks (ImageJ hyperstacks, OME-TIFF): axes, physical sizes, LZW and other codecs
        "tifffile>=2023.1",
        "imagecodecs>=2023.1",
        "matplotlib>=3.6",
        "tqdm>=4.60",
    ],
    # test: what the tests import besides the core (vispy/PyOpenGL: the peer rows of the benchmark)
    extras_require={"test": ["pytest>=7", "pytest-xdist>=3", "scipy>=1.9", "hypothesis>=6", "pydicom-data", "vispy>=0.14",
                             "PyOpenGL>=3.1"],
                    # peers beside VTK in `mipcast bench --peers` and the GPU report (never required)
                    "bench": ["vispy>=0.14", "PyOpenGL>=3.1"]},
    entry_points={"console_scripts": ["mipcast=mipcast.app.cli:main"]},
)

"""Siemens MOSAIC files, generated with pydicom, CSA header bytes included.

The true volume is defined first (tile size, spacing, first voxel, row and
column cosines, slice normal); the mosaic's header is then written the way
Siemens scanners write it: ImagePositionPatient is that of the top-left pixel
of the whole mosaic seen as one image, i.e. the first voxel moved back by
half the extra rows and columns of the mosaic (nibabel's "dicom_mosaic"
notes).  The test checks the reader against the true volume.
"""
import math
import struct

import numpy as np
import pytest

pydicom = pytest.importorskip("pydicom")
from pydicom.uid import generate_uid  # noqa: E402
from test_dicom import ds_numbers, base_dataset, direction, physical, rotation, save  # noqa: E402

from mipcast.io.dicom import DicomError, read_dicom  # noqa: E402
from mipcast.core.validation import check_image  # noqa: E402

MR_IMAGE = "1.2.840.10008.5.1.4.1.1.4"


def csa2(tags):
    """CSA2 ('SV10') header bytes; ``tags`` maps name -> (VR, [values as strings])."""
    out = [b"SV10", b"\x04\x03\x02\x01", struct.pack("<2I", len(tags), 77)]
    for name, (vr, values) in tags.items():
        out.append(struct.pack("<64si4s3i", name.encode(), len(values), vr.encode(), 0,
                               len(values), 77))
        for value in values:
            data = value.encode() + b"\x00"
            out.append(struct.pack("<4i", len(data), len(data), 77, len(data)))
            out.append(data + b"\x00" * (-len(data) % 4))
    return b"".join(out)


class Mosaic:
    def __init__(self, n=35, tile=(8, 6), spacing=(0.7, 0.9), step=3.5, rot=rotation(20, 30),
                 flip_normal=False, first=(-40.0, 12.5, 30.25)):
        self.n, (self.tr, self.tc) = n, tile
        self.size = math.ceil(math.sqrt(n))
        self.spacing, self.step = spacing, step
        self.iop = np.round(np.concatenate([rot[:, 0], rot[:, 1]]), 8)
        self.row, self.col = self.iop[:3], self.iop[3:]
        cross = np.cross(self.row, self.col)
        self.normal = -cross if flip_normal else cross  # the CSA SliceNormalVector
        self.first = np.array(first)

    def tile_pixels(self, k):
        r, c = np.mgrid[0:self.tr, 0:self.tc]
        return 1000 + 50 * k + 7 * r + c

    def voxel(self, c, r, k):
        """Patient position of column c, row r of slice k of the true volume."""
        return (self.first + c * self.spacing[1] * self.row + r * self.spacing[0] * self.col
                + k * self.step * self.normal)

    def write(self, path, csa_count=True, private_count=False, image_type=True):
        rows, cols = self.size * self.tr, self.size * self.tc
        slab = np.zeros((rows, cols), np.int16)
        for k in range(self.n):
            r0, c0 = (k // self.size) * self.tr, (k % self.size) * self.tc
            slab[r0:r0 + self.tr, c0:c0 + self.tc] = self.tile_pixels(k)
        # Siemens: IPP of the mosaic's top-left pixel, as if it were one big slice
        ipp = (self.first - (rows - self.tr) / 2 * self.spacing[0] * self.col
               - (cols - self.tc) / 2 * self.spacing[1] * self.row)
        ds = base_dataset(MR_IMAGE, generate_uid(), modality="MR")
        ds.Manufacturer = "SIEMENS"
        ds.ImageType = ["ORIGINAL", "PRIMARY", "M", "ND", "MOSAIC"] if image_type else ["ORIGINAL"]
        ds.ImagePositionPatient = ds_numbers(ipp, 6)
        ds.ImageOrientationPatient = ds_numbers(self.iop, 8)
        ds.PixelSpacing = ds_numbers(self.spacing, 4)
        ds.SliceThickness = "3"
        ds.SpacingBetweenSlices = f"{self.step:g}"
        ds.Rows, ds.Columns = rows, cols
        ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
        tags = {"AcquisitionMatrixText": ("SH", [f"{self.tr}p*{self.tc}"]),
                "SliceNormalVector": ("FD", [f"{v:.8f}" for v in self.normal])}
        if csa_count:
            tags["NumberOfImagesInMosaic"] = ("US", [str(self.n)])
        block = ds.private_block(0x0029, "SIEMENS CSA HEADER", create=True)
        block.add_new(0x10, "OB", csa2(tags))
        if private_count:
            ds.private_block(0x0019, "SIEMENS MR HEADER", create=True).add_new(0x0A, "US", self.n)
        ds.PixelData = slab.tobytes()
        save(ds, path)
        return path


@pytest.mark.parametrize("flip", [False, True], ids=["normal", "flipped-normal"])
def test_mosaic_is_unpacked_with_the_true_geometry(tmp_path, flip):
    mosaic = Mosaic(flip_normal=flip)
    image = read_dicom(mosaic.write(tmp_path / "mosaic.dcm"))
    assert image.GetDimensions() == (mosaic.tc, mosaic.tr, mosaic.n) == (6, 8, 35)
    assert image.GetSpacing() == pytest.approx((0.9, 0.7, 3.5), abs=1e-6)
    np.testing.assert_allclose(direction(image)[:, 0], mosaic.row, atol=1e-6)
    np.testing.assert_allclose(direction(image)[:, 1], mosaic.col, atol=1e-6)
    values = check_image(image)
    for k in range(mosaic.n):
        # the reader orders slices along row x column; find slice k there
        kk = mosaic.n - 1 - k if flip else k
        np.testing.assert_array_equal(values[kk], mosaic.tile_pixels(k))
        for c, r in [(0, 0), (5, 7), (2, 3)]:
            np.testing.assert_allclose(physical(image, c, r, kk), mosaic.voxel(c, r, k), atol=1e-4)


def test_mosaic_count_from_the_private_tag(tmp_path):
    mosaic = Mosaic(n=7, tile=(4, 4))
    image = read_dicom(mosaic.write(tmp_path / "m.dcm", csa_count=False, private_count=True))
    assert image.GetDimensions() == (4, 4, 7)
    np.testing.assert_allclose(physical(image, 0, 0, 6), mosaic.voxel(0, 0, 6), atol=1e-4)


def test_mosaic_without_a_count_is_refused(tmp_path):
    path = Mosaic(n=7, tile=(4, 4)).write(tmp_path / "m.dcm", csa_count=False)
    with pytest.raises(DicomError, match="NumberOfImagesInMosaic"):
        read_dicom(path)


def test_csa_normal_contradicting_the_orientation_is_refused(tmp_path):
    mosaic = Mosaic(n=4, tile=(4, 4))
    mosaic.normal = mosaic.row.copy()  # not perpendicular to the slices
    with pytest.raises(DicomError, match="SliceNormalVector"):
        read_dicom(mosaic.write(tmp_path / "m.dcm"))


def test_a_35_slice_384_pixel_mosaic_like_the_reported_one(tmp_path):
    # 35 tiles of 64 x 64 in a 6 x 6 grid: 384 x 384 pixels, read before as one flat slice
    mosaic = Mosaic(n=35, tile=(64, 64), spacing=(3.0, 3.0), step=3.6, rot=rotation(-8, 12))
    image = read_dicom(mosaic.write(tmp_path / "mosaic.dcm"))
    assert image.GetDimensions() == (64, 64, 35)
    assert image.GetSpacing() == pytest.approx((3.0, 3.0, 3.6), abs=1e-6)
    for c, r, k in [(0, 0, 0), (63, 63, 34), (10, 50, 17)]:
        np.testing.assert_allclose(physical(image, c, r, k), mosaic.voxel(c, r, k), atol=1e-4)
    np.testing.assert_array_equal(check_image(image)[34], mosaic.tile_pixels(34))

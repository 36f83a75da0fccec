"""Writes a volume (x, y, z array with its RAS affine, as nibabel gives them) as a DICOM series of one
slice a file with pydicom, the classic layout scanners write: slice k of the array's third axis in
file k, rows along the array's second axis and columns along its first. Geometry in DICOM's LPS."""
import os

import numpy as np
import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, MRImageStorage, RLELossless, generate_uid

LPS = np.diag([-1.0, -1.0, 1.0])


def _ds(text):
    return f"{float(text):.10g}"


def write_series(folder, data, affine, slope=1.0, intercept=0.0, series_uid=None, positions=None, tilt=None,
                 shuffle=True, rle=False):
    """Writes data (int16 after (value - intercept) / slope) into folder/slice_K.dcm; returns the
    SeriesInstanceUID. positions: slice positions to use instead of the affine's (to make uneven
    spacing); tilt: a GantryDetectorTilt to write. Files are named out of slice order when shuffle.
    rle: the pixels compressed (RLE Lossless, the one compressed transfer syntax pydicom writes)."""
    os.makedirs(folder, exist_ok=True)
    series_uid = series_uid or generate_uid()
    study_uid = generate_uid()
    linear = LPS @ affine[:3, :3]
    row, column = linear[:, 0], linear[:, 1]
    spacing = [np.linalg.norm(column), np.linalg.norm(row)]  # PixelSpacing: between rows, then columns
    orientation = list(row / spacing[1]) + list(column / spacing[0])
    stored = np.round((np.asarray(data, dtype=np.float64) - intercept) / slope).astype(np.int16)
    nz = data.shape[2]
    order = np.random.default_rng(7).permutation(nz) if shuffle else np.arange(nz)
    for k in range(nz):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = MRImageStorage
        meta.MediaStorageSOPInstanceUID = generate_uid()
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        path = os.path.join(folder, f"slice_{order[k]:04d}.dcm")
        ds = FileDataset(path, {}, file_meta=meta, preamble=b"\0" * 128)
        ds.is_little_endian, ds.is_implicit_VR = True, False
        ds.SOPClassUID, ds.SOPInstanceUID = MRImageStorage, meta.MediaStorageSOPInstanceUID
        ds.StudyInstanceUID, ds.SeriesInstanceUID = study_uid, series_uid
        ds.Modality, ds.PatientName, ds.PatientID = "MR", "isoatlas^test", "isoatlas-test"
        ds.SeriesNumber, ds.InstanceNumber = 1, k + 1
        position = LPS @ (affine[:3, :3] @ [0, 0, k] + affine[:3, 3]) if positions is None else positions[k]
        ds.ImagePositionPatient = [_ds(x) for x in position]
        ds.ImageOrientationPatient = [_ds(x) for x in orientation]
        ds.PixelSpacing = [_ds(x) for x in spacing]
        ds.SliceThickness = _ds(np.linalg.norm(linear[:, 2]))
        if tilt is not None:
            ds.GantryDetectorTilt = _ds(tilt)
        ds.Rows, ds.Columns = data.shape[1], data.shape[0]
        ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
        ds.RescaleSlope, ds.RescaleIntercept = _ds(slope), _ds(intercept)
        ds.PixelData = np.ascontiguousarray(stored[:, :, k].T).tobytes()
        if rle:
            ds.compress(RLELossless)
        ds.save_as(path, write_like_original=False)
    return series_uid

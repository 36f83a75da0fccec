"""DICOM series in: series written by pydicom from a crop of ch2, in two orientations and with a
rescale, read back voxel for voxel and affine for affine against the same volume as NIfTI; dcm2niix's
conversion of the same series agrees with ours in world space; the command reads a folder, picks a
series with --series (searching subfolders; so does the window), and refuses uneven spacing, gantry
tilt and a folder of several series with one line each."""
import os
import subprocess

import nibabel as nib
import numpy as np
import pytest

import isoatlas
from dicom_series import write_series

EXE = os.environ["ISOATLAS_EXE"]
HERE = os.path.dirname(os.path.abspath(__file__))
CH2 = os.path.join(HERE, "..", "..", "data", "volumes", "ch2.nii.gz")


def rotation(axis, degrees):
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    i, j = [k for k in range(3) if k != axis]
    r = np.eye(3)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


def ch2_crop(orientation):
    """A 40 x 36 x 12 crop of ch2 (int16) and its RAS affine: axial as ch2 lies, or oblique (the
    axes permuted to sagittal slices, turned 20 degrees, anisotropic voxels)."""
    img = nib.load(CH2)
    data = np.asarray(img.dataobj)[70:110, 90:126, 80:92].astype(np.int16)
    affine = img.affine.copy()
    affine[:3, 3] += affine[:3, :3] @ [70, 90, 80]
    if orientation == "axial":
        return data, affine
    data = np.ascontiguousarray(np.transpose(data, (1, 2, 0)))  # slices along the old x: sagittal
    linear = rotation(2, 20) @ affine[:3, :3][:, [1, 2, 0]] @ np.diag([0.9, 1.3, 2.0])
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = linear, affine[:3, 3]
    return data, out


def run(*args):
    return subprocess.run([EXE, *args], capture_output=True, text=True)


@pytest.mark.parametrize("orientation", ["axial", "oblique"])
@pytest.mark.parametrize("slope,intercept", [(1.0, 0.0), (0.5, -100.0)])
def test_a_series_reads_as_its_nifti(tmp_path, orientation, slope, intercept):
    data, affine = ch2_crop(orientation)
    values = data * slope + intercept
    write_series(str(tmp_path / "series"), values, affine, slope=slope, intercept=intercept)
    nib.save(nib.Nifti1Image(values.astype(np.float32), affine), str(tmp_path / "same.nii.gz"))
    dicom = isoatlas.read_volume(str(tmp_path / "series"))
    nifti = isoatlas.read_volume(str(tmp_path / "same.nii.gz"))
    assert tuple(dicom.shape) == data.shape
    np.testing.assert_allclose(dicom.affine, nifti.affine, atol=1e-4)
    np.testing.assert_array_equal(np.asarray(dicom.data, dtype=np.float64), np.asarray(nifti.data, dtype=np.float64))
    assert dicom.data.dtype == (np.int16 if slope == 1 and intercept == 0 else np.float32)
    # One file of the series names it too.
    one = sorted(os.listdir(tmp_path / "series"))[3]
    np.testing.assert_array_equal(isoatlas.read_volume(str(tmp_path / "series" / one)).data, dicom.data)


def test_a_compressed_series_reads_as_the_uncompressed_one(tmp_path):
    """RLE Lossless pixels (GDCM decodes them) give the uncompressed series' voxels and affine."""
    data, affine = ch2_crop("oblique")
    write_series(str(tmp_path / "plain"), data, affine)
    write_series(str(tmp_path / "rle"), data, affine, rle=True)
    plain, rle = isoatlas.read_volume(str(tmp_path / "plain")), isoatlas.read_volume(str(tmp_path / "rle"))
    np.testing.assert_array_equal(rle.data, plain.data)
    np.testing.assert_allclose(rle.affine, plain.affine, atol=1e-6)
    assert np.asarray(plain.data).any()


@pytest.mark.parametrize("orientation", ["axial", "oblique"])
def test_dcm2niix_agrees_in_world_space(tmp_path, orientation):
    data, affine = ch2_crop(orientation)
    write_series(str(tmp_path / "series"), data * 0.5 - 100, affine, slope=0.5, intercept=-100)
    subprocess.run(["dcm2niix", "-z", "n", "-b", "n", "-f", "converted", "-o", str(tmp_path), str(tmp_path / "series")],
                   check=True, capture_output=True)
    theirs = nib.load(str(tmp_path / "converted.nii"))
    ours = isoatlas.read_volume(str(tmp_path / "series"))
    # Their voxel grid is ours reordered: the map between the two index spaces is a signed
    # permutation with a whole-voxel shift.
    index = np.linalg.inv(theirs.affine) @ ours.affine
    assert np.allclose(index, np.round(index), atol=1e-3), index
    index = np.round(index).astype(int)
    ijk = np.indices(ours.shape).reshape(3, -1)
    there = index[:3, :3] @ ijk + index[:3, 3:4]
    theirs_data = theirs.get_fdata()
    assert (there >= 0).all() and (there < np.array(theirs_data.shape)[:, None]).all()
    np.testing.assert_allclose(theirs_data[tuple(there)], np.asarray(ours.data).reshape(-1), atol=1e-3)


def test_the_command_reads_a_folder_and_picks_a_series(tmp_path):
    data, affine = ch2_crop("axial")
    folder = tmp_path / "study"
    first = write_series(str(folder / "a"), data, affine)
    second = write_series(str(folder / "b"), data[:, :, :6], affine)
    for sub in ("a", "b"):  # one folder of two series, files named apart
        for name in os.listdir(folder / sub):
            os.rename(folder / sub / name, folder / f"{sub}_{name}")
    result = run("info", str(folder))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "2 DICOM series" in lines[0] and first in lines[0] and second in lines[0] and "--series" in lines[0]
    result = run("info", str(folder), "--series", second, "--report", str(tmp_path / "info.json"))
    assert result.returncode == 0, result.stderr
    assert "40 x 36 x 6" in result.stdout
    result = run("extract", str(folder), "--series", first, "--iso", "60", "-o", str(tmp_path / "surface.ply"))
    assert result.returncode == 0, result.stderr
    assert run("info", str(folder), "--series", "1.2.3").returncode == 2


def _no_series_file(path):
    """A DICOM file without a SeriesInstanceUID, as a DICOMDIR at a study's top is."""
    from pydicom.dataset import FileDataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = "1.2.840.10008.1.3.10"  # Media Storage Directory Storage
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = FileDataset(path, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.is_little_endian, ds.is_implicit_VR = True, False
    ds.FileSetID = "ISOATLAS"
    ds.save_as(path, write_like_original=False)


def test_a_study_folder_is_searched_with_its_subfolders(tmp_path):
    """A PACS export's layout: study/PATIENT/SERIES/files, a DICOMDIR-like file at the top. The
    study's two series are found in their subfolders (listed, then picked with --series), a series'
    own subfolder reads alone, and the file without a series is passed over."""
    data, affine = ch2_crop("axial")
    study = tmp_path / "study"
    first = write_series(str(study / "P1" / "SE1"), data, affine)
    second = write_series(str(study / "P1" / "SE2" / "deeper"), data[:, :, :6], affine)
    _no_series_file(str(study / "DICOMDIR"))
    result = run("info", str(study))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "2 DICOM series" in lines[0] and first in lines[0] and second in lines[0], result.stderr
    result = run("info", str(study), "--series", second)
    assert result.returncode == 0, result.stderr
    assert "40 x 36 x 6" in result.stdout
    whole = isoatlas.read_volume(str(study), series=first)
    alone = isoatlas.read_volume(str(study / "P1" / "SE1"))
    assert np.array_equal(np.asarray(whole.data), np.asarray(alone.data))
    assert np.array_equal(np.asarray(whole.data), data)
    empty = tmp_path / "empty"
    empty.mkdir()
    _no_series_file(str(empty / "DICOMDIR"))
    result = run("info", str(empty))
    assert result.returncode == 2 and "holds no DICOM series" in result.stderr, result.stderr


def test_the_window_opens_a_study_folder_and_picks_its_series(tmp_path):
    """isoatlas view on a study folder of two series (under Xvfb, llvmpipe): with --series the picked
    one opens (its mask, saved by the script, has that series' grid); without it, one line lists them."""
    data, affine = ch2_crop("axial")
    study = tmp_path / "study"
    write_series(str(study / "SE1"), data, affine)
    second = write_series(str(study / "SE2"), data[:, :, :6], affine)
    script, mask = tmp_path / "s.txt", tmp_path / "mask.nii.gz"
    script.write_text(f"save-mask {mask}\nquit\n")
    view = ["xvfb-run", "-a", "-s", "-screen 0 640x480x24", EXE, "view", str(study), "--size", "480,320", "--backend", "cpu",
            "--script", str(script)]
    result = subprocess.run(view + ["--series", second], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert nib.load(str(mask)).shape == (40, 36, 6)
    mask.unlink()
    result = subprocess.run(view, capture_output=True, text=True)
    assert result.returncode == 2 and "2 DICOM series" in result.stderr and second in result.stderr, result.stderr
    assert not mask.exists()


@pytest.mark.parametrize("fault,message", [("uneven", "uneven slice spacing"), ("tilt", "gantry tilt"),
                                           ("sheared", "not stacked along their normal")])
def test_a_bad_series_is_refused_with_one_line(tmp_path, fault, message):
    data, affine = ch2_crop("axial")
    positions = [np.diag([-1.0, -1.0, 1.0]) @ (affine[:3, :3] @ [0, 0, k] + affine[:3, 3]) for k in range(data.shape[2])]
    if fault == "uneven":
        positions = [p + [0, 0, 0.5 * (k >= 6)] for k, p in enumerate(positions)]
    if fault == "sheared":
        positions = [p + [0, 0.4 * k, 0] for k, p in enumerate(positions)]
    write_series(str(tmp_path / "series"), data, affine, positions=positions, tilt=12.0 if fault == "tilt" else None)
    out = tmp_path / "mask.nii.gz"
    result = run("segment", str(tmp_path / "series"), "--seed", "20,18,6", "--target", "80", "--width", "20", "-o", str(out))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.stderr
    assert not out.exists()
    with pytest.raises(ValueError, match=message):
        isoatlas.read_volume(str(tmp_path / "series"))


def test_a_cohort_row_of_a_dicom_folder_is_run_again_when_a_slice_changes(tmp_path):
    from isoatlas.cohort.manifest import DEFAULTS, Subject
    from isoatlas.cohort.subject import input_hash
    data, affine = ch2_crop("axial")
    write_series(str(tmp_path / "series"), data, affine)
    subject = Subject(id="s", volume=str(tmp_path / "series"), seeds=[(0.0, 0.0, 0.0, 3.0)], target=80, width=20, alpha=0.8)
    before = input_hash(subject, DEFAULTS, ["segment"])
    assert input_hash(subject, DEFAULTS, ["segment"]) == before
    one = tmp_path / "series" / sorted(os.listdir(tmp_path / "series"))[5]
    original = one.read_bytes()
    one.write_bytes(original[:-1] + bytes([original[-1] ^ 1]))  # one voxel's lowest bit
    assert input_hash(subject, DEFAULTS, ["segment"]) != before
    one.write_bytes(original)
    assert input_hash(subject, DEFAULTS, ["segment"]) == before



def test_a_cohort_row_of_a_study_folder_hashes_its_subfolders(tmp_path):
    from isoatlas.cohort.manifest import DEFAULTS, Subject
    from isoatlas.cohort.subject import input_hash
    data, affine = ch2_crop("axial")
    write_series(str(tmp_path / "study" / "SE1"), data, affine)
    subject = Subject(id="s", volume=str(tmp_path / "study"), seeds=[(0.0, 0.0, 0.0, 3.0)], target=80, width=20, alpha=0.8)
    before = input_hash(subject, DEFAULTS, ["segment"])
    one = tmp_path / "study" / "SE1" / sorted(os.listdir(tmp_path / "study" / "SE1"))[3]
    original = one.read_bytes()
    one.write_bytes(original[:-1] + bytes([original[-1] ^ 1]))
    assert input_hash(subject, DEFAULTS, ["segment"]) != before, "a slice in a subfolder changed unseen"
    one.write_bytes(original)
    assert input_hash(subject, DEFAULTS, ["segment"]) == before
    os.rename(tmp_path / "study" / "SE1", tmp_path / "study" / "SE2")
    assert input_hash(subject, DEFAULTS, ["segment"]) != before, "the subfolder's name is part of the input"

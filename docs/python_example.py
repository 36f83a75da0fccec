"""docs/python.md's example: a NIfTI scan to a rendered multiresolution model, from Python.
Run from the checkout after building: PYTHONPATH=build/release/python python3 docs/python_example.py"""
import nibabel as nib
import isoatlas

img = nib.load("data/volumes/ch2.nii.gz")                       # Colin27's T1 (scripts/fetch-data)
mask, phi, report = isoatlas.segment(img, seeds=[(64, 115, 101, 4), (116, 115, 101, 4)],
                                     target=112, width=14, alpha=0.8, iterations=3000, converge=True)
vertices, triangles = isoatlas.extract(phi, iso=0, largest=True, affine=img.affine)
model = isoatlas.build(vertices, triangles)                      # base mesh + atlas, as `isoatlas build`
model.save("wm.isoatlas")
isoatlas.write_png("wm.png", isoatlas.render(model, width=800, height=600, cpu_level=4))
nib.save(nib.Nifti1Image(mask, img.affine), "wm_mask.nii.gz")
# psnr_base_db: the base mesh's accuracy against the surface (build's figure); isoatlas.eval gives each level's
print(f"{report['iterations']} steps, {len(triangles)} triangles, {model.tiles} tiles, base mesh PSNR {model.report['psnr_base_db']:.1f} dB")

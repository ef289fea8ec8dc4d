"""The Euler-Poincare law F - E + V - L = 2(B - G) on a part with holes and a cavity.

A block with two through-holes (genus 2) and a spherical cavity inside (a
second shell: B = 2).  Its mesh is grouped into faces by CSG leaf and the
vertices, edges, faces and inner loops counted (`spatial.compare.brep`):
the law holds with B = 2, G = 2.  Picture: the part cut open at y = 0.
"""

from _gallery import image_axes, plt, pv_picture, save
from implicit import box, cylinder, sphere
from spatial import mesh
from spatial.compare import brep


def main(out_dir=None, small=False):
    N = 32 if small else 96
    part = box((4.0, 2.0, 2.0)) - cylinder(0.35, 3, center=(-1.2, 0, 0)) - cylinder(0.35, 3, center=(1.2, 0, 0)) \
        - sphere(0.55)
    m = mesh(part, resolution=N)
    rep = brep(part, m)
    assert (rep.B, rep.G) == (2, 2) and rep.holds
    lhs, rhs = rep.euler_poincare
    cut = m.clip_closed_surface(normal=(0, 1, 0), origin=(0, 0, 0))
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.6), gridspec_kw={"width_ratios": [1.4, 1]})
    image_axes(a, pv_picture([(cut, {"color": "#c8a165"})], (560, 380) if not small else (280, 200),
                             view=(0.6, -1.6, 0.9)), "block, two through-holes, a spherical cavity (cut at y = 0)")
    b.set_axis_off()
    rows = [("faces F", rep.F), ("edges E", rep.E), ("vertices V", rep.V), ("inner loops L", rep.L),
            ("bodies (shells) B", rep.B), ("genus G", rep.G)]
    text = "\n".join(f"{name:<20}{value:>4}" for name, value in rows)
    text += f"\n\nF - E + V - L = {rep.F} - {rep.E} + {rep.V} - {rep.L} = {lhs}\n2 (B - G)     = 2 ({rep.B} - {rep.G})" \
            f" = {rhs}\n\n{'holds' if rep.holds else 'FAILS'}"
    b.text(0.02, 0.95, text, va="top", family="monospace", fontsize=11)
    b.set_title("Euler-Poincare law for a closed object", fontsize=11)
    fig.tight_layout()
    return save(fig, "euler_poincare", out_dir)


if __name__ == "__main__":
    print(main())

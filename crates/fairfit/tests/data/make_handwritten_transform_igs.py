# Writes handwritten_transform.igs (see README.md): every entity and field chosen by hand; run from this folder.
h = "0.70710678118654757"
start = ["Written by hand for fairfit's IGES reader tests (tests/data/README.md):",
         "inch units, custom delimiters / and #, a 124 transform, a 126 trimmed by",
         "V(0), V(1), D exponents, parameter-space curves and a line to skip."]
def H(t):
    return f"{len(t)}H{t}"
name = H("handwritten, a.igs")
glob = (f"1H//1H#/{name}/{name}/{H('fairfit')}/{H('by hand')}/32/38/6/308/15/"
        f"{name}/1.0D0/1/{H('INCH')}/1/0.01/{H('20261126.190000')}/1.D-7/11.0/{H('me,')}/{H('us,')}/11/0/"
        f"{H('20261126.190000')}#")
ents = []
# DE 1: 124 rotation by 90 deg about z, then translation (10, 0, 0)
ents.append((124, "124/0./-1./0./10./1./0./0./0./0./0./1./0.#", 0, "00000000"))
# DE 3: quarter circle radius 1 (rational quadratic), V(0)=0.25, V(1)=1, transformed by DE 1
ents.append((126, f"126/2/2/1/0/0/0/0./0./0./1./1./1./1.D0/{h}/1.0D+00/1./0./0./1./1./0./0./1./0./0.25/1./0./0./1.#", 1, "00000000"))
# DE 5: a parameter-space curve (entity use 05), to be skipped
ents.append((126, "126/1/1/1/0/1/0/0./0./1./1./1./1./0./0./0./1./1./0./0./1./0./0./1.#", 0, "00000500"))
# DE 7: a line, which is no B-spline
ents.append((110, "110/0./0./0./1./1./0.#", 0, "00000000"))
# DE 9: a cubic Bezier, polynomial, weights all 2 (the same curve as weights 1), D exponents
ents.append((126, "126/3/3/1/0/1/0/0./0./0./0./1./1./1./1./2.D0/2.D0/2.D0/2.D0/"
                  "0./0./0./1.D0/2.D0/0./3.D0/2.D0/0./4.D0/0./0./0./1./0./0./1.#", 0, "00000000"))
# DE 11: a parameter-space line as a 126 without the entity use flag, DE 13: the 102 composite holding
# it, DE 15: a 142 curve on a surface whose BPTR is that composite: the reader must skip DE 11
ents.append((126, "126/1/1/1/0/1/0/0./0./1./1./1./1./0./0./0./1./1./0./0./1./0./0./1.#", 0, "00000000"))
ents.append((102, "102/1/11#", 0, "00000000"))
ents.append((142, "142/0/0/13/0/1#", 0, "00000000"))
def line(text, letter, seq):
    assert len(text) <= 72, text
    return f"{text:<72}{letter}{seq:>7}"
out = [line(s, 'S', i + 1) for i, s in enumerate(start)]
g = [glob[i:i + 72] for i in range(0, len(glob), 72)]
out += [line(s, 'G', i + 1) for i, s in enumerate(g)]
pd, de = [], []
for k, (kind, params, xf, status) in enumerate(ents):
    seq = 2 * k + 1
    first = len(pd) + 1
    chunks, cur = [], ""
    for tok in params.replace("#", "#\0").replace("/", "/\0").split("\0"):
        if not tok:
            continue
        if len(cur) + len(tok) > 64:
            chunks.append(cur); cur = ""
        cur += tok
    chunks.append(cur)
    for c in chunks:
        pd.append(f"{c:<64} {seq:>7}")
    de.append(f"{kind:>8}{first:>8}{0:>8}{0:>8}{0:>8}{0:>8}{xf:>8}{0:>8}{status:>8}D{seq:>7}")
    de.append(f"{kind:>8}{0:>8}{0:>8}{len(chunks):>8}{0:>8}{'':>8}{'':>8}{'':>8}{0:>8}D{seq + 1:>7}")
out += de
out += [f"{p}P{i + 1:>7}" for i, p in enumerate(pd)]
out.append(line(f"S{len(start):07}G{len(g):07}D{len(de):07}P{len(pd):07}", 'T', 1))
assert all(len(l) == 80 for l in out), [len(l) for l in out]
open("handwritten_transform.igs", "w", newline="").write("\r\n".join(out) + "\r\n")

#!/usr/bin/env python3
"""cond(Jp) and cond(Jo) of the compiled PATHOS-II (Table 1 / Table 3 model) at
50 significant digits, independently of the C++ code.

Model (docs/mechanisms/pathos2.md, core/mechanisms/pathos2/pathos2.h):
  leg base  B_i = Tz(L) Rx(theta_b1) Rz(120 deg k) Tz(db) Ry(theta_t) Tx(lx)
  leg chain Rz(t1) Tz(l1) Ry(t2) Tz(l2) Rx(t3) Tz(l3) -> globular centre
  attachment in E: Rx(theta_b1) Tz(-h0) Rz(120 deg k) Tx(lp)
  pose R = Rz(rz) Ry(ry) Rx(rx); branch = sign of c1y = -l3 sin t3 with
  c1x = sin t2 (l2 + l3 cos t3) >= 0 (+1 legs 1-3, -1 legs 4-6).

Each leg is solved from its own forward chain (closed form, then checked by
closure to 1e-45 cm); da/dt is mpmath's derivative of the chain; dt1/dP is
the first row of its inverse; rows [g_i, rho_i x g_i] stack to M
(qdot = M twist, twist = [v; omega], rho_i from E to the globular centre);
J = M^-1, Jp its top three rows, Jo its bottom three, cond the ratio of the
extreme singular values (mpmath.svd_r). With --check the first pose's M is
also compared with mpmath's derivative of the whole pose IK along each twist
direction (a rotation exp(eps omega^) R), a check of the assembly.

The poses: the README pose (0, 0, 22.5, 0, 0, 0.5236, 7) and the 36 centred
level poses x = y = 0, rx = ry = 0, grip 7 cm, z in {19, 20.5, 22, 23.5,
25, 26.5} cm, rz in {0, 12, 24, 36, 48, 60} deg (three-fold symmetric about
z: the two horizontal singular values of Jp, and of Jo, coincide).

Run (python3-mpmath):  python3 tests/reference/pathos2_cond_mpmath.py [--check]
It prints the C++ table of tests/core/mechanisms/pathos2/pathos2_cond_reference.inc.
"""
import math
import sys

import mpmath as mp

mp.mp.dps = 60

L0, LB, L1, L2, L3, LP = (mp.mpf(v) for v in (45, 10, 7, 14, 6, 2))
THETA_T = mp.pi / 6
DB = LB * mp.tan(THETA_T)
LX = LB / mp.cos(THETA_T)
BRANCH = [1, 1, 1, -1, -1, -1]


def rx(a):
    c, s = mp.cos(a), mp.sin(a)
    return mp.matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a):
    c, s = mp.cos(a), mp.sin(a)
    return mp.matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a):
    c, s = mp.cos(a), mp.sin(a)
    return mp.matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def vec(x, y, z):
    return mp.matrix([x, y, z])


def cross(a, b):
    return vec(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def legs():
    """(R_world_B, p_world_B, attachment in E) per leg."""
    out = []
    for i in range(6):
        upper, k = i >= 3, i % 3
        flip = rx(mp.pi) if upper else mp.eye(3)
        around = flip * rz(2 * mp.pi * k / 3)
        R_B = around * ry(THETA_T)
        p_B = vec(0, 0, L0 if upper else 0) + around * (vec(0, 0, DB) + ry(THETA_T) * vec(LX, 0, 0))
        attach = flip * (vec(0, 0, -H0) + rz(2 * mp.pi * k / 3) * vec(LP, 0, 0))
        out.append((R_B, p_B, attach))
    return out


def leg_forward(t1, t2, t3):
    return rz(t1) * (vec(0, 0, L1) + ry(t2) * (vec(0, 0, L2) + rx(t3) * vec(0, 0, L3)))


def leg_inverse(a, branch):
    """(t1, t2, t3) with leg_forward = a: from |a - l1 z| the elbow t3 (sign
    of c1y = -l3 sin t3 = branch), then t2 and t1 from c1 = Rz(-t1) a."""
    dz = a[2] - L1
    rho2 = a[0] ** 2 + a[1] ** 2 + dz ** 2
    c3 = (rho2 - L2 ** 2 - L3 ** 2) / (2 * L2 * L3)
    t3 = -branch * mp.acos(c3)  # c1y = -l3 sin t3 has the branch's sign
    w = L2 + L3 * mp.cos(t3)
    c1y = -L3 * mp.sin(t3)
    c1x = mp.sqrt(a[0] ** 2 + a[1] ** 2 - c1y ** 2)
    t2 = mp.atan2(c1x / w, dz / w)
    t1 = mp.atan2(a[1], a[0]) - mp.atan2(c1y, c1x)
    t = (t1, t2, t3)
    closure = mp.norm(leg_forward(*t) - a)
    assert closure < mp.mpf(10) ** -45, closure
    return t


def leg_jacobian(t):
    """da/dt by mpmath's differentiation of the chain."""
    D = mp.matrix(3, 3)
    for j in range(3):
        for r in range(3):
            def f(x, j=j, r=r):
                u = list(t)
                u[j] = x
                return leg_forward(*u)[r]
            D[r, j] = mp.diff(f, t[j])
    return D


def pose_rotation(rx_, ry_, rz_):
    return rz(rz_) * ry(ry_) * rx(rx_)


def globular_centres(p, R):
    return [p + R * attach for (_, _, attach) in LEGS]


def actuator_angles(p, R):
    q = []
    for i, (R_B, p_B, _) in enumerate(LEGS):
        a = R_B.T * (globular_centres(p, R)[i] - p_B)
        q.append(leg_inverse(a, BRANCH[i])[0])
    return q


def M_of(p, R):
    M = mp.matrix(6, 6)
    for i, ((R_B, p_B, _), P) in enumerate(zip(LEGS, globular_centres(p, R))):
        a = R_B.T * (P - p_B)
        grad_a = mp.inverse(leg_jacobian(leg_inverse(a, BRANCH[i])))[0, :]  # dt1/da, a row
        g = R_B * grad_a.T
        m = cross(P - p, g)
        for c in range(3):
            M[i, c] = g[c]
            M[i, 3 + c] = m[c]
    return M


def skew(w):
    return mp.matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def M_by_differentiating_the_ik(p, R):
    M = mp.matrix(6, 6)
    for c in range(6):
        e = [0] * 6
        e[c] = 1
        v, w = vec(*e[:3]), vec(*e[3:])
        for i in range(6):
            M[i, c] = mp.diff(lambda s: actuator_angles(p + s * v, mp.expm(s * skew(w)) * R)[i], 0)
    return M


def condition(B):
    s = mp.svd_r(B, compute_uv=False)
    return max(s) / min(s)


def conds(pose, check=False):
    x, y, z, rx_, ry_, rz_, h0 = (mp.mpf(v) for v in pose)  # the doubles' exact values
    global H0, LEGS
    H0 = h0
    LEGS = legs()
    p, R = vec(x, y, z), pose_rotation(rx_, ry_, rz_)
    M = M_of(p, R)
    if check:
        diff = mp.mnorm(M - M_by_differentiating_the_ik(p, R), 1) / mp.mnorm(M, 1)
        print(f"// check: |M - dq/dtwist|_1 / |M|_1 = {mp.nstr(diff, 3)}", file=sys.stderr)
    J = mp.inverse(M)
    return condition(J[0:3, :]), condition(J[3:6, :])


def poses():
    """As doubles (the test's inputs): rz = deg * (pi / 180) rounded as C++ does."""
    yield (0.0, 0.0, 22.5, 0.0, 0.0, 0.5236, 7.0)  # the README pose
    for z in (19.0, 20.5, 22.0, 23.5, 25.0, 26.5):
        for deg in (0, 12, 24, 36, 48, 60):
            yield (0.0, 0.0, z, 0.0, 0.0, deg * (math.pi / 180.0), 7.0)


def main():
    check = "--check" in sys.argv
    print("// cond(Jp) and cond(Jo) of the Table 3 PATHOS-II at 50-digit accuracy (mpmath,")
    print("// 60-digit working precision, printed to 30 digits), independent of the C++ model:")
    print("// {x, y, z, rx, ry, rz, h0, cond(Jp), cond(Jo)}; the README pose, then the 36 centred")
    print("// level poses. Regenerate with")
    print("//   python3 tests/reference/pathos2_cond_mpmath.py > tests/core/mechanisms/pathos2/pathos2_cond_reference.inc")
    for n, pose in enumerate(poses()):
        cp, co = conds(pose, check and n == 0)
        print("{" + ", ".join(repr(v) for v in pose) + ", " + mp.nstr(cp, 30) + ", " + mp.nstr(co, 30) + "},")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
# Used by bench/setup-mistakes/run: apply_mistake.py IN OUT MISTAKE (inverted, setup, transposed,
# xyzw_as_wxyz, wxyz_as_xyzw, m_as_mm, mm_as_m, scale=F, shift, same_image). scale=F declares the
# target F times its size: every size key it has (square, marker, tag) times F.
"""Makes one usual setup mistake to a handeye-observations/1 file (4x4 T_base_ee poses)."""
import json, math, sys

def inv(T):
    R = [[T[c][r] for c in range(3)] for r in range(3)]
    t = [-sum(R[r][c] * T[c][3] for c in range(3)) for r in range(3)]
    return [R[0] + [t[0]], R[1] + [t[1]], R[2] + [t[2]], [0, 0, 0, 1]]

def quat(R):  # (w, x, y, z)
    tr = R[0][0] + R[1][1] + R[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1) * 2
        return ((s / 4), (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s)
    i = max(range(3), key=lambda k: R[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1 + R[i][i] - R[j][j] - R[k][k]) * 2
    q = [0, 0, 0, 0]
    q[0] = (R[k][j] - R[j][k]) / s
    q[1 + i] = s / 4
    q[1 + j] = (R[j][i] + R[i][j]) / s
    q[1 + k] = (R[k][i] + R[i][k]) / s
    return tuple(q)

def rot(q):
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]

def with_rotation(T, R):
    return [R[r] + [T[r][3]] for r in range(3)] + [[0, 0, 0, 1]]

src, dst, mistake = sys.argv[1:4]
d = json.load(open(src))
poses = d['poses']
Ts = [p['T_base_ee'] for p in poses]
if mistake == 'inverted':
    Ts = [inv(T) for T in Ts]
elif mistake == 'setup':
    d['setup'] = 'eye_in_hand' if d['setup'] == 'eye_to_hand' else 'eye_to_hand'
elif mistake == 'transposed':
    Ts = [with_rotation(T, [[T[c][r] for c in range(3)] for r in range(3)]) for T in Ts]
elif mistake == 'xyzw_as_wxyz':  # file x,y,z,w read as w,x,y,z
    Ts = [with_rotation(T, rot(quat([row[:3] for row in T[:3]])[1:] + quat([row[:3] for row in T[:3]])[:1])) for T in Ts]
elif mistake == 'wxyz_as_xyzw':  # file w,x,y,z read as x,y,z,w
    Ts = [with_rotation(T, rot(quat([row[:3] for row in T[:3]])[3:] + quat([row[:3] for row in T[:3]])[:3])) for T in Ts]
elif mistake in ('m_as_mm', 'mm_as_m'):
    f = 0.001 if mistake == 'm_as_mm' else 1000.0
    Ts = [[row[:3] + [row[3] * f] for row in T[:3]] + [[0, 0, 0, 1]] for T in Ts]
elif mistake.startswith('scale='):
    f = float(mistake.split('=')[1])
    for key in ('square_size_m', 'marker_size_m', 'tag_size_m'):
        if key in d['target']:
            d['target'][key] *= f
elif mistake == 'shift':
    Ts = Ts[1:] + Ts[:1]
elif mistake == 'same_image':
    first = {}
    for o in d['observations']:
        f = first.setdefault(o['camera'], o)
        o['ids'], o['points_px'] = f['ids'], f['points_px']
else:
    sys.exit('unknown mistake ' + mistake)
for p, T in zip(poses, Ts):
    p['T_base_ee'] = T
json.dump(d, open(dst, 'w'))

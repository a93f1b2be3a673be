"""A compiled DOP853 driver for the Stribeck scene, in numba: the peer `benches/stribeck_peers.py`
measures stickslip against. Pinned: numba==0.68.1 (numpy 2.4).

The same physics and the event logic of `scipy_stribeck.py` (a careful user's driver, not
stickslip's: no search for a crossing and return inside one step, no Stribeck peak guard, and a
step that starts at belt speed is not searched for a return to it — cheaper, and events it misses
show as mismatched realizations):
mass-spring on a belt of velocity s*V0 whose sign flips at given instants; the stick in closed
form (x = x0 + v t, breakaway at x_b = (s mu_s N - c v)/k); the slip integrated by DOP853
(Hairer's coefficients, error estimate and controller: E. Hairer, S. P. Norsett, G. Wanner,
Solving ODEs I, II.10) with the Stribeck law; the return to belt speed found as a sign change of
g = sigma (v - xdot) at a step's end and located on the seventh-order dense output (computed only
then, as Hairer's driver does) by the Illinois method; there the mass sticks if the spring force
is within the static limit, else the friction reverses. Everything is compiled (one njit loop over
the realizations); the timed part excludes the compilation and the loading of the inputs.
"""
import numpy as np
from numba import njit

M, K, C, N = 1.0, 4.0, 0.0, 9.8
MU_K, MU_S, VS = 0.51, 0.6, 0.1
V0, TA = 1.0, 10.0

# DOP853 (Hairer): stage rows as (index, coefficient) pairs, the solution row (b), the dense
# output's extra stages (13-15), the error weights and the dense output's weights.
_ROWS = {
    1: [(0, 5.26001519587677318785587544488e-2)],
    2: [(0, 1.97250569845378994544595329183e-2), (1, 5.91751709536136983633785987549e-2)],
    3: [(0, 2.95875854768068491816892993775e-2), (2, 8.87627564304205475450678981324e-2)],
    4: [(0, 2.41365134159266685502369798665e-1), (2, -8.84549479328286085344864962717e-1), (3, 9.24834003261792003115737966543e-1)],
    5: [(0, 3.7037037037037037037037037037e-2), (3, 1.70828608729473871279604482173e-1), (4, 1.25467687566822425016691814123e-1)],
    6: [(0, 3.7109375e-2), (3, 1.70252211019544039314978060272e-1), (4, 6.02165389804559606850219397283e-2), (5, -1.7578125e-2)],
    7: [(0, 3.70920001185047927108779319836e-2), (3, 1.70383925712239993810214054705e-1), (4, 1.07262030446373284651809199168e-1),
        (5, -1.53194377486244017527936158236e-2), (6, 8.27378916381402288758473766002e-3)],
    8: [(0, 6.24110958716075717114429577812e-1), (3, -3.36089262944694129406857109825), (4, -8.68219346841726006818189891453e-1),
        (5, 2.75920996994467083049415600797e1), (6, 2.01540675504778934086186788979e1), (7, -4.34898841810699588477366255144e1)],
    9: [(0, 4.77662536438264365890433908527e-1), (3, -2.48811461997166764192642586468), (4, -5.90290826836842996371446475743e-1),
        (5, 2.12300514481811942347288949897e1), (6, 1.52792336328824235832596922938e1), (7, -3.32882109689848629194453265587e1),
        (8, -2.03312017085086261358222928593e-2)],
    10: [(0, -9.3714243008598732571704021658e-1), (3, 5.18637242884406370830023853209), (4, 1.09143734899672957818500254654),
         (5, -8.14978701074692612513997267357), (6, -1.85200656599969598641566180701e1), (7, 2.27394870993505042818970056734e1),
         (8, 2.49360555267965238987089396762), (9, -3.0467644718982195003823669022)],
    11: [(0, 2.27331014751653820792359768449), (3, -1.05344954667372501984066689879e1), (4, -2.00087205822486249909675718444),
         (5, -1.79589318631187989172765950534e1), (6, 2.79488845294199600508499808837e1), (7, -2.85899827713502369474065508674),
         (8, -8.87285693353062954433549289258), (9, 1.23605671757943030647266201528e1), (10, 6.43392746015763530355970484046e-1)],
    12: [(0, 5.42937341165687622380535766363e-2), (5, 4.45031289275240888144113950566), (6, 1.89151789931450038304281599044),
         (7, -5.8012039600105847814672114227), (8, 3.1116436695781989440891606237e-1), (9, -1.52160949662516078556178806805e-1),
         (10, 2.01365400804030348374776537501e-1), (11, 4.47106157277725905176885569043e-2)],
    13: [(0, 5.61675022830479523392909219681e-2), (6, 2.53500210216624811088794765333e-1), (7, -2.46239037470802489917441475441e-1),
         (8, -1.24191423263816360469010140626e-1), (9, 1.5329179827876569731206322685e-1), (10, 8.20105229563468988491666602057e-3),
         (11, 7.56789766054569976138603589584e-3), (12, -8.298e-3)],
    14: [(0, 3.18346481635021405060768473261e-2), (5, 2.83009096723667755288322961402e-2), (6, 5.35419883074385676223797384372e-2),
         (7, -5.49237485713909884646569340306e-2), (10, -1.08347328697249322858509316994e-4), (11, 3.82571090835658412954920192323e-4),
         (12, -3.40465008687404560802977114492e-4), (13, 1.41312443674632500278074618366e-1)],
    15: [(0, -4.28896301583791923408573538692e-1), (5, -4.69762141536116384314449447206), (6, 7.68342119606259904184240953878),
         (7, 4.06898981839711007970213554331), (8, 3.56727187455281109270669543021e-1), (12, -1.39902416515901462129418009734e-3),
         (13, 2.9475147891527723389556272149), (14, -9.15095847217987001081870187138)],
}
_E5 = [(0, 0.1312004499419488073250102996e-1), (5, -0.1225156446376204440720569753e1), (6, -0.4957589496572501915214079952),
       (7, 0.1664377182454986536961530415e1), (8, -0.3503288487499736816886487290), (9, 0.3341791187130174790297318841),
       (10, 0.8192320648511571246570742613e-1), (11, -0.2235530786388629525884427845e-1)]
_BHH = [(0, 0.244094488188976377952755905512), (8, 0.733846688281611857341361741547), (11, 0.220588235294117647058823529412e-1)]
_D = [
    [(0, -0.84289382761090128651353491142e1), (5, 0.56671495351937776962531783590), (6, -0.30689499459498916912797304727e1),
     (7, 0.23846676565120698287728149680e1), (8, 0.21170345824450282767155149946e1), (9, -0.87139158377797299206789907490),
     (10, 0.22404374302607882758541771650e1), (11, 0.63157877876946881815570249290), (12, -0.88990336451333310820698117400e-1),
     (13, 0.18148505520854727256656404962e2), (14, -0.91946323924783554000451984436e1), (15, -0.44360363875948939664310572000e1)],
    [(0, 0.10427508642579134603413151009e2), (5, 0.24228349177525818288430175319e3), (6, 0.16520045171727028198505394887e3),
     (7, -0.37454675472269020279518312152e3), (8, -0.22113666853125306036270938578e2), (9, 0.77334326684722638389603898808e1),
     (10, -0.30674084731089398182061213626e2), (11, -0.93321305264302278729567221706e1), (12, 0.15697238121770843886131091075e2),
     (13, -0.31139403219565177677282850411e2), (14, -0.93529243588444783865713862664e1), (15, 0.35816841486394083752465898540e2)],
    [(0, 0.19985053242002433820987653617e2), (5, -0.38703730874935176555105901742e3), (6, -0.18917813819516756882830838328e3),
     (7, 0.52780815920542364900561016686e3), (8, -0.11573902539959630126141871134e2), (9, 0.68812326946963000169666922661e1),
     (10, -0.10006050966910838403183860980e1), (11, 0.77771377980534432092869265740), (12, -0.27782057523535084065932004339e1),
     (13, -0.60196695231264120758267380846e2), (14, 0.84320405506677161018159903784e2), (15, 0.11992291136182789328035130030e2)],
    [(0, -0.25693933462703749003312586129e2), (5, -0.15418974869023643374053993627e3), (6, -0.23152937917604549567536039109e3),
     (7, 0.35763911791061412378285349910e3), (8, 0.93405324183624310003907691704e2), (9, -0.37458323136451633156875139351e2),
     (10, 0.10409964950896230045147246184e3), (11, 0.29840293426660503123344363579e2), (12, -0.43533456590011143754432175058e2),
     (13, 0.96324553959188282948394950600e2), (14, -0.39177261675615439165231486172e2), (15, -0.14972683625798562581422125276e3)],
]


def _sparse(rows):
    """Rows of (index, coefficient) pairs as padded index and coefficient arrays and lengths."""
    width = max(len(r) for r in rows)
    idx = np.zeros((len(rows), width), np.int64)
    coef = np.zeros((len(rows), width))
    nnz = np.zeros(len(rows), np.int64)
    for i, r in enumerate(rows):
        nnz[i] = len(r)
        for j, (k, c) in enumerate(r):
            idx[i, j], coef[i, j] = k, c
    return idx, coef, nnz


A_IDX, A_COEF, A_NNZ = _sparse([[(0, 0.0)]] + [_ROWS[s] for s in range(1, 16)])  # (row 0: stage 0 is f(y0))
E_IDX, E_COEF, _ = _sparse([_E5])
H_IDX, H_COEF, _ = _sparse([_BHH])
D_IDX, D_COEF, _ = _sparse(_D)


@njit(inline="always", error_model="numpy")
def accel(x, xd, v, sigma):
    u = v - xd
    f = N * (MU_K + (MU_S - MU_K) * np.exp(-(u / VS) ** 2))
    return (sigma * f - K * x - C * xd) / M


@njit(inline="always", error_model="numpy")
def stage(s, x0, xd0, h, kx, kv, v, sigma):
    """Stage s from the earlier ones: its state, and its derivative stored in kx, kv."""
    x, xd = x0, xd0
    for j in range(A_NNZ[s]):
        i, c = A_IDX[s, j], A_COEF[s, j]
        x += h * c * kx[i]
        xd += h * c * kv[i]
    kx[s] = xd
    kv[s] = accel(x, xd, v, sigma)
    return x, xd


@njit(error_model="numpy")
def dense(x0, xd0, x1, xd1, h, kx, kv, v, sigma, out):
    """The dense output's seven coefficient pairs (Hairer's CONTD8) into out[0..7, 0..2]."""
    for s in range(13, 16):
        stage(s, x0, xd0, h, kx, kv, v, sigma)
    dx, dv = x1 - x0, xd1 - xd0
    out[0, 0], out[0, 1] = dx, dv
    out[1, 0], out[1, 1] = h * kx[0] - dx, h * kv[0] - dv
    out[2, 0], out[2, 1] = dx - h * kx[12] - out[1, 0], dv - h * kv[12] - out[1, 1]
    for r in range(4):
        sx, sv = 0.0, 0.0
        for j in range(D_IDX.shape[1]):
            i, c = D_IDX[r, j], D_COEF[r, j]
            sx += c * kx[i]
            sv += c * kv[i]
        out[3 + r, 0], out[3 + r, 1] = h * sx, h * sv


@njit(inline="always", error_model="numpy")
def at(theta, x0, xd0, cont, comp):
    t, u = theta, 1.0 - theta
    d = cont[3, comp] + t * (cont[4, comp] + u * (cont[5, comp] + t * cont[6, comp]))
    y0 = x0 if comp == 0 else xd0
    return y0 + t * (cont[0, comp] + u * (cont[1, comp] + t * (cont[2, comp] + u * d)))


@njit(error_model="numpy")
def realization(x0, xd0, sign0, switches, rtol, sticks, slips):
    """One realization; stick and slip start times into the buffers; (n_sticks, n_slips, steps)."""
    kx = np.zeros(16)
    kv = np.zeros(16)
    cont = np.zeros((7, 2))
    n_st, n_sl, steps = 0, 0, 0
    t, x, xd, s = 0.0, x0, xd0, sign0
    stuck = False
    at_belt = s  # the friction direction of a slip that starts at belt speed
    h = 1e-3
    n_seg = switches.shape[0] + 1
    for seg in range(n_seg):
        t_end = switches[seg] if seg < switches.shape[0] else TA
        v = s * V0
        fresh = True  # the next step starts at belt speed (after a breakaway or a reversal)
        fsal = False  # the last stage of the previous step is f at this step's start
        while t < t_end:
            if stuck:
                xb = (s * MU_S * N - C * v) / K
                tb = t + (xb - x) / v
                if tb < t_end:
                    t, x, xd, stuck = tb, xb, v, False
                    at_belt = s
                    if n_st > 0:
                        slips[n_sl] = t
                        n_sl += 1
                    fresh, fsal = True, False
                else:
                    x, t = x + v * (t_end - t), t_end
                continue
            sigma = np.sign(v - xd) if xd != v else at_belt
            # one accepted DOP853 step (first stage: the last one of the previous step, FSAL)
            if fsal:
                kx[0], kv[0] = kx[12], kv[12]
            else:
                kx[0], kv[0] = xd, accel(x, xd, v, sigma)
            while True:
                hh = min(h, t_end - t)
                for st in range(1, 12):
                    stage(st, x, xd, hh, kx, kv, v, sigma)
                x1, xd1 = stage(12, x, xd, hh, kx, kv, v, sigma)
                e5, e3 = 0.0, 0.0
                for comp in range(2):
                    k = kx if comp == 0 else kv
                    y0 = x if comp == 0 else xd
                    y1 = x1 if comp == 0 else xd1
                    sk = rtol + rtol * max(abs(y0), abs(y1))
                    er5, b = 0.0, 0.0
                    for j in range(E_IDX.shape[1]):
                        er5 += E_COEF[0, j] * k[E_IDX[0, j]]
                    for j in range(A_NNZ[12]):
                        b += A_COEF[12, j] * k[A_IDX[12, j]]
                    for j in range(H_IDX.shape[1]):
                        b -= H_COEF[0, j] * k[H_IDX[0, j]]
                    e5 += (hh * er5 / sk) ** 2
                    e3 += (hh * b / sk) ** 2
                deno = e5 + 0.01 * e3
                err = e5 / np.sqrt(2.0 * deno) if deno > 0.0 else 0.0
                steps += 1
                fac = min(3.0, max(1.0 / 6.0, err ** 0.125 / 0.9))
                if err <= 1.0:
                    if hh == h:
                        h = h / fac
                    break
                h = hh / min(3.0, err ** 0.125 / 0.9)
            g0, g1 = sigma * (v - xd), sigma * (v - xd1)
            if g1 <= 0.0 and (g0 > 0.0 or not fresh):
                # located on the dense output: the Illinois method on g(theta)
                dense(x, xd, x1, xd1, hh, kx, kv, v, sigma, cont)
                a, b = 0.0, 1.0
                fa, fb = g0, g1
                side = 0
                for _ in range(200):
                    if b - a <= 1e-15 or fb == 0.0:
                        break
                    m = (a * fb - b * fa) / (fb - fa)
                    if not (a < m < b):
                        m = 0.5 * (a + b)
                    fm = sigma * (v - at(m, x, xd, cont, 1))
                    if fm > 0.0:
                        a, fa = m, fm
                        if side == -1:
                            fb *= 0.5
                        side = -1
                    else:
                        b, fb = m, fm
                        if side == 1:
                            fa *= 0.5
                        side = 1
                t = t + b * hh
                x, xd = at(b, x, xd, cont, 0), v
                if abs(K * x + C * v) <= MU_S * N:
                    stuck = True
                    sticks[n_st] = t
                    n_st += 1
                else:
                    at_belt = np.sign(K * x + C * v)
                fresh, fsal = True, False
            else:
                t, x, xd = t + hh, x1, xd1
                fresh, fsal = False, True
        if seg < switches.shape[0]:
            if stuck:
                stuck = False
                if n_st > 0:
                    slips[n_sl] = t
                    n_sl += 1
            s = -s
    return n_st, n_sl, steps


@njit(error_model="numpy")
def run(x0, xd0, sign0, switch_flat, switch_off, rtol, sticks, slips, counts):
    """All realizations: event times into rows of `sticks`/`slips`, counts into `counts`."""
    total = 0
    for r in range(x0.shape[0]):
        sw = switch_flat[switch_off[r]:switch_off[r + 1]]
        n_st, n_sl, steps = realization(x0[r], xd0[r], sign0[r], sw, rtol, sticks[r], slips[r])
        counts[r, 0], counts[r, 1] = n_st, n_sl
        total += steps
    return total

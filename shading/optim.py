"""Small optimisers in numpy only (Blender's Python has no scipy): bounded least squares, Nelder-Mead.

``bvls(A, b, lower, upper)`` solves min ||A x - b||_2 subject to lower <= x <= upper for small dense
problems (a few columns, any number of rows) with the active-set method of Stark and Parker. It works
on the n x n triangular factor R of A = QR (so the conditioning is that of A, not of A^T A) and stops
when the Karush-Kuhn-Tucker conditions hold: with the negative gradient w = A^T (b - A x),

    w_j = 0 for free x_j,   w_j <= 0 for x_j at its lower bound,   w_j >= 0 for x_j at its upper bound.

``nelder_mead(f, x0, xatol, fatol, maxiter)`` is the downhill simplex method with the standard
coefficients (reflection 1, expansion 2, contraction 1/2, shrink 1/2; optionally Gao-Han's adaptive
ones) as specified by Lagarias et al.: the same initial simplex (5 % steps, 0.00025 for zero
components), the same order of trial points and the same stopping test (simplex size <= xatol in
every coordinate and function spread <= fatol) as scipy.optimize.minimize(method="Nelder-Mead").

References
----------
P. B. Stark, R. L. Parker, "Bounded-variable least-squares: an algorithm and applications",
Computational Statistics 10 (1995) 129-141.
C. L. Lawson, R. J. Hanson, *Solving Least Squares Problems* (1974), ch. 23 (the NNLS active set).
J. A. Nelder, R. Mead, "A simplex method for function minimization", Computer Journal 7 (1965) 308.
J. C. Lagarias, J. A. Reeds, M. H. Wright, P. E. Wright, "Convergence properties of the Nelder-Mead
simplex method in low dimensions", SIAM J. Optim. 9 (1998) 112-147 (the variant used here).
F. Gao, L. Han, "Implementing the Nelder-Mead simplex algorithm with adaptive parameters",
Computational Optimization and Applications 51 (2012) 259-277.
"""

from dataclasses import dataclass, field

import numpy as np

__all__ = ["OptimResult", "bvls", "kkt_violation", "nelder_mead"]


@dataclass
class OptimResult:
    """Result of :func:`bvls` or :func:`nelder_mead`.

    Attributes
    ----------
    x : numpy.ndarray
        The solution.
    fun : float
        The objective there (``bvls``: 0.5 ||A x - b||^2, as scipy's ``cost``).
    nit : int
        Iterations (``bvls``: variables moved into the free set).
    nfev : int
        Objective evaluations (``nelder_mead``; 0 for ``bvls``).
    status : int
        0 converged, 1 evaluation limit, 2 iteration limit.
    message : str
    success : bool
    """

    x: np.ndarray
    fun: float
    nit: int = 0
    nfev: int = 0
    status: int = 0
    message: str = ""
    success: bool = True
    extra: dict = field(default_factory=dict)


def kkt_violation(A, b, x, lower, upper):
    """Largest violation of the KKT conditions of min ||A x - b|| on the box (units of A^T b).

    0 at the exact solution: max over free x_j of |w_j|, over x_j at the lower bound of max(w_j, 0),
    at the upper bound of max(-w_j, 0), with w = A^T (b - A x); inf if x is outside the box.
    """
    A = np.asarray(A, dtype=float)
    x = np.asarray(x, dtype=float)
    lo, hi = (np.broadcast_to(np.asarray(v, dtype=float), x.shape) for v in (lower, upper))
    if np.any(x < lo) or np.any(x > hi):
        return np.inf
    w = A.T @ (np.asarray(b, dtype=float) - A @ x)
    at_lo, at_hi = x <= lo, x >= hi
    v = np.where(at_lo & at_hi, 0.0, np.where(at_lo, np.maximum(w, 0.0), np.where(at_hi, np.maximum(-w, 0.0),
                                                                                  np.abs(w))))
    return float(np.max(v)) if v.size else 0.0


def bvls(A, b, lower=0.0, upper=1.0, max_iter=None):
    """Bounded-variable least squares: argmin ||A x - b||_2 with lower <= x <= upper (Stark-Parker).

    Parameters
    ----------
    A : array_like, shape (m, n)
        Design matrix (any units; n small: each iteration solves an n x n triangular system).
    b : array_like, shape (m,)
    lower, upper : float or array_like, shape (n,)
        Bounds (may be -inf / inf); lower <= upper.
    max_iter : int, optional
        Limit on variables freed (default 10 n + 20).

    Returns
    -------
    OptimResult
        ``x`` (n,), ``fun`` = 0.5 ||A x - b||^2, ``status`` 0 when the KKT conditions hold to
        ``extra['tol']`` (a few ulps of ||A|| (||b|| + ||A|| ||x||)), 2 at the iteration limit.

    References
    ----------
    Stark & Parker (1995); Lawson & Hanson (1974) ch. 23 (module docstring).
    """
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float)
    if A.ndim != 2 or b.shape != (A.shape[0],):
        raise ValueError(f"A must be (m, n) and b (m,), got {A.shape} and {b.shape}")
    m, n = A.shape
    lo = np.array(np.broadcast_to(np.asarray(lower, dtype=float), (n,)))
    hi = np.array(np.broadcast_to(np.asarray(upper, dtype=float), (n,)))
    if np.any(lo > hi) or np.any(np.isnan(lo)) or np.any(np.isnan(hi)):
        raise ValueError("every lower bound must be <= its upper bound")
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
        raise ValueError("A and b must be finite")
    if m > n:
        Q, R = np.linalg.qr(A)  # reduced: ||A x - b||^2 = ||R x - Q^T b||^2 + const
        c = Q.T @ b
    else:
        R, c = A, b
    # state: -1 at lower bound, +1 at upper bound, 0 free
    state = np.where(np.isfinite(lo), -1, np.where(np.isfinite(hi), 1, 0))
    x = np.where(state == -1, lo, np.where(state == 1, hi, 0.0))
    norm_r, norm_c = np.linalg.norm(R), np.linalg.norm(c)
    max_iter = 10 * n + 20 if max_iter is None else int(max_iter)

    def solve_free(entering, came_from=0):
        """Inner loop: minimise over the free set, stepping back onto bounds; False if 'entering' fails."""
        nonlocal x
        for _ in range(3 * n + 3):
            free = np.flatnonzero(state == 0)
            if free.size == 0:
                return True
            bound = np.flatnonzero(state != 0)
            rhs = c - R[:, bound] @ x[bound]
            z = np.linalg.lstsq(R[:, free], rhs, rcond=None)[0]
            if entering is not None:
                k = int(np.flatnonzero(free == entering)[0])
                # the entering variable must move into the box, else its gradient sign was rounding
                if (z[k] - x[entering]) * -came_from <= 0:
                    state[entering] = came_from
                    return False
                entering = None
            inside = (z > lo[free]) & (z < hi[free])
            if np.all(inside):
                x[free] = z
                return True
            # step from x towards z until the first free variable meets a bound
            xf = x[free]
            with np.errstate(divide="ignore", invalid="ignore"):
                t_lo = np.where(z <= lo[free], (xf - lo[free]) / (xf - z), np.inf)
                t_hi = np.where(z >= hi[free], (hi[free] - xf) / (z - xf), np.inf)
            t = np.nan_to_num(np.minimum(t_lo, t_hi), nan=0.0)
            alpha = float(np.clip(np.min(t), 0.0, 1.0))
            x[free] = xf + alpha * (z - xf)
            hit_lo = free[(t_lo <= alpha) | (x[free] <= lo[free])]
            hit_hi = free[(t_hi <= alpha) | (x[free] >= hi[free])]
            x[hit_lo], state[hit_lo] = lo[hit_lo], -1
            x[hit_hi], state[hit_hi] = hi[hit_hi], 1
        return True

    solve_free(None)  # variables without finite bounds start free
    nit, status = 0, 0
    movable = lo < hi  # a variable with lower == upper is a constant
    while True:
        w = R.T @ (c - R @ x)
        # rounding in w is a few ulps of ||R|| (||c|| + ||R|| ||x||): smaller |w| counts as 0
        tol = 16.0 * np.finfo(float).eps * n * norm_r * (norm_c + norm_r * np.linalg.norm(x))
        forbidden = ~movable
        moved = False
        while True:
            cand = (~forbidden) & (((state == -1) & (w > tol)) | ((state == 1) & (w < -tol)))
            if not cand.any():
                break
            j = int(np.argmax(np.where(cand, np.abs(w), -np.inf)))
            x_before, state_before = x.copy(), state.copy()
            state[j] = 0
            if solve_free(j, state_before[j]):
                state_before[j] = state[j]
                if not (np.array_equal(x, x_before) and np.array_equal(state, state_before)):
                    moved = True
                    break
                state[j] = state_before[j]  # freeing j changed nothing: try the next candidate
            forbidden[j] = True
        if not moved:
            break
        nit += 1
        if nit >= max_iter:
            status = 2
            break
    x = np.clip(x, lo, hi)
    r = A @ x - b
    return OptimResult(x=x, fun=0.5 * float(r @ r), nit=nit, status=status, success=status == 0,
                       message="KKT conditions hold" if status == 0 else "iteration limit reached",
                       extra={"tol": tol, "active": state.copy()})


def nelder_mead(fun, x0, xatol=1e-4, fatol=1e-4, maxiter=None, maxfev=None, adaptive=False):
    """Minimise ``fun(x) -> float`` from ``x0`` by the Nelder-Mead simplex method (no derivatives).

    Parameters
    ----------
    fun : callable
        Objective of a 1-d float array (receives a copy).
    x0 : array_like, shape (n,)
        Start; the initial simplex adds 5 % of each nonzero component (0.00025 for zero ones).
    xatol, fatol : float
        Stop when every vertex is within ``xatol`` of the best in every coordinate AND every function
        value within ``fatol`` of the best (units of x and of fun).
    maxiter, maxfev : int, optional
        Iteration / evaluation limits; both default to 200 n, one given leaves the other unlimited.
    adaptive : bool
        Gao-Han coefficients 1, 1 + 2/n, 0.75 - 1/(2n), 1 - 1/n (for many dimensions).

    Returns
    -------
    OptimResult
        ``x`` the best vertex, ``fun`` its value, ``nit``, ``nfev``, ``status`` (0 converged,
        1 maxfev, 2 maxiter); ``extra['final_simplex']`` = (vertices, values).

    References
    ----------
    Nelder & Mead (1965); Lagarias et al. (1998); Gao & Han (2012) (module docstring).
    """
    x0 = np.asarray(x0, dtype=float).ravel()
    n = len(x0)
    if adaptive:
        rho, chi, psi, sigma = 1.0, 1.0 + 2.0 / n, 0.75 - 1.0 / (2.0 * n), 1.0 - 1.0 / n
    else:
        rho, chi, psi, sigma = 1.0, 2.0, 0.5, 0.5
    if maxiter is None and maxfev is None:
        maxiter = maxfev = 200 * n
    elif maxiter is None:
        maxiter = 200 * n if maxfev == np.inf else np.inf
    elif maxfev is None:
        maxfev = 200 * n if maxiter == np.inf else np.inf
    sim = np.empty((n + 1, n))
    sim[0] = x0
    for k in range(n):
        y = x0.copy()
        y[k] = 1.05 * y[k] if y[k] != 0 else 0.00025
        sim[k + 1] = y
    nfev = 0

    class _Limit(Exception):
        pass

    def f(x):
        nonlocal nfev
        if nfev >= maxfev:
            raise _Limit
        nfev += 1
        value = fun(np.copy(x))
        value = np.asarray(value, dtype=float)
        if value.size != 1:
            raise ValueError("the objective must return one number")
        return float(value.reshape(()))

    fsim = np.full(n + 1, np.inf)
    try:
        for k in range(n + 1):
            fsim[k] = f(sim[k])
    except _Limit:
        pass
    order = np.argsort(fsim)
    sim, fsim = sim[order], fsim[order]
    nit = 1
    try:
        while nfev < maxfev and nit < maxiter:
            if np.max(np.abs(sim[1:] - sim[0])) <= xatol and np.max(np.abs(fsim[0] - fsim[1:])) <= fatol:
                break
            xbar = np.add.reduce(sim[:-1], 0) / n  # centroid of all but the worst vertex
            xr = (1 + rho) * xbar - rho * sim[-1]
            fxr = f(xr)
            shrink = False
            if fxr < fsim[0]:
                xe = (1 + rho * chi) * xbar - rho * chi * sim[-1]
                fxe = f(xe)
                if fxe < fxr:
                    sim[-1], fsim[-1] = xe, fxe
                else:
                    sim[-1], fsim[-1] = xr, fxr
            elif fxr < fsim[-2]:
                sim[-1], fsim[-1] = xr, fxr
            elif fxr < fsim[-1]:  # outside contraction
                xc = (1 + psi * rho) * xbar - psi * rho * sim[-1]
                fxc = f(xc)
                if fxc <= fxr:
                    sim[-1], fsim[-1] = xc, fxc
                else:
                    shrink = True
            else:  # inside contraction
                xcc = (1 - psi) * xbar + psi * sim[-1]
                fxcc = f(xcc)
                if fxcc < fsim[-1]:
                    sim[-1], fsim[-1] = xcc, fxcc
                else:
                    shrink = True
            if shrink:
                for j in range(1, n + 1):
                    sim[j] = sim[0] + sigma * (sim[j] - sim[0])
                    fsim[j] = f(sim[j])
            nit += 1
            order = np.argsort(fsim)
            sim, fsim = sim[order], fsim[order]
    except _Limit:
        order = np.argsort(fsim)
        sim, fsim = sim[order], fsim[order]
    if nfev >= maxfev:
        status, message = 1, "maximum number of function evaluations reached"
    elif nit >= maxiter:
        status, message = 2, "maximum number of iterations reached"
    else:
        status, message = 0, "converged (xatol and fatol met)"
    return OptimResult(x=sim[0].copy(), fun=float(np.min(fsim)), nit=nit, nfev=nfev, status=status,
                       message=message, success=status == 0, extra={"final_simplex": (sim.copy(), fsim.copy())})

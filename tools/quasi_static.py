"""The quasi-static spectrum of docs/model.md §7.5 in numpy, apart from the program's C++
(src/theory/quasi_static.cpp, which uses Lanczos and other node counts): the ratio of the
quasi-static to the first-order C_x for poisson renewal, N contacts at coupling eps.

Each contact's uniform force on Gauss-Legendre nodes; the symmetric functions of the N forces
on the multisets of nodes; the time-weighted generator u L symmetrised and diagonalised."""

import math

import numpy as np
from numpy.polynomial.legendre import leggauss


def _multisets(n_items, types):
    if types == 1:
        return [[n_items]]
    return [[c] + rest for c in range(n_items, -1, -1) for rest in _multisets(n_items - c, types - 1)]


def _nodes_for(n_items, limit=1500):
    n = 2
    while n < 24 and math.comb(n_items + n, n) <= limit:
        n += 1
    return n


class QuasiStatic:
    """Ratio to the first order at omega / (v/a); eps below the stall sqrt(2 / (3 N))."""

    def __init__(self, n_items, eps, nodes=None):
        n = nodes or _nodes_for(n_items)
        half_width = eps * math.sqrt(6.0 / n_items) / 2  # a force's range, in F_drive - F_kin
        x, w = leggauss(n)
        x, w = x * half_width, w / 2
        states = np.array(_multisets(n_items, n))
        index = {tuple(c): i for i, c in enumerate(states)}
        log_w = np.log(w)
        pi = np.exp([math.lgamma(n_items + 1) - sum(math.lgamma(c + 1) for c in s) + s @ log_w for s in states])
        g = states @ x
        u = 1 - g
        a = np.zeros((len(states), len(states)))
        for i, c in enumerate(states):
            for k in np.nonzero(c)[0]:
                a[i, i] -= u[i] * c[k] * (1 - w[k])
                for m in range(n):
                    if m != k:
                        d = c.copy()
                        d[k] -= 1
                        d[m] += 1
                        j = index[tuple(d)]
                        a[i, j] = math.sqrt(u[i] * u[j] * c[k] * w[m] * (c[m] + 1) * w[k])
        inverse_speed = np.sum(pi / u)
        q = np.sqrt(pi / u) * (g - np.sum(pi * g / u) / inverse_speed)
        values, vectors = np.linalg.eigh(a)
        keep = np.abs(values) > 1e-10 * np.max(np.abs(values))
        self.values = values[keep]
        self.weights = (vectors.T @ q)[keep] ** 2 / inverse_speed
        self.first = n_items * half_width**2 / 3
        self.mean_speed = 1 / inverse_speed  # V / v

    def ratio(self, omega_over_rate):
        z = -1j * np.atleast_1d(np.asarray(omega_over_rate, dtype=float))[:, None]
        phi = np.sum(self.weights / (z - self.values), axis=1)
        return phi.real / (self.first / (z[:, 0] + 1)).real

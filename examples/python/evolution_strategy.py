#!/usr/bin/env python3
"""An evolution strategy that tunes the diffusion controller's parameters (velocity, alpha, delta)
for coverage: the share of the arena's floor, in 0.25 m cells, that some robot has been over.

One process, one Simulation: each individual is evaluated by setting its parameters
(sim.set_controller_param), resetting (sim.reset: no file read, no plugin loaded again) and
running, reading the robots' positions as numpy arrays every few ticks. A (mu/mu, lambda)-ES: each
generation samples LAMBDA individuals around the mean, keeps the MU best, and moves the mean to
their average; numpy only. Every individual of a generation runs with the same seed, so they are
compared on the same start.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/evolution_strategy.py
        [--generations 20] [--population 20] [--seconds 30] [--robots 30] [--threads 2]"""
import argparse
import os
import sys

import numpy as np

import colony

HERE = os.path.dirname(os.path.abspath(__file__))
EXPERIMENT = os.path.join(HERE, "..", "..", "experiments", "diffusion.xml")
CELL = 0.25   # m: the coverage grid
ARENA = 8.0   # m: experiments/diffusion.xml's arena, walls included
# The genome: velocity (m/s), alpha (degrees), delta, each kept within what the controller accepts
# (controllers/diffusion/diffusion.cpp) and a sensible range.
NAMES = ("velocity", "alpha", "delta")
LOW = np.array([0.0, 0.0, 0.0])
HIGH = np.array([0.3, 90.0, 1.0])


def coverage(sim, sample_every=5):
    """Runs the simulation to its end; returns the share of grid cells some robot was in."""
    cells = int(round(ARENA / CELL))
    seen = np.zeros((cells, cells), dtype=bool)
    while not sim.done:
        sim.run(sample_every)
        xy = sim.robots.positions[:, :2]
        ij = np.clip(((xy + ARENA / 2) / CELL).astype(int), 0, cells - 1)
        seen[ij[:, 0], ij[:, 1]] = True
    return seen.mean()


def evaluate(sim, genome, seed):
    for name, value in zip(NAMES, genome):
        sim.set_controller_param("dc", name, float(value))
    sim.reset(seed=seed)
    return coverage(sim)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--generations", type=int, default=20)
    p.add_argument("--population", type=int, default=20, help="lambda, individuals per generation")
    p.add_argument("--seconds", type=float, default=30, help="simulated seconds per evaluation")
    p.add_argument("--robots", type=int, default=30)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=0, help="the strategy's own random seed")
    a = p.parse_args()
    if a.generations < 1 or a.population < 2:
        p.error("--generations must be >= 1 and --population >= 2")

    sim = colony.Simulation(EXPERIMENT, threads=a.threads,
                            set={"arena.distribute.entity.quantity": a.robots,
                                 "framework.experiment.length": a.seconds,
                                 "output.metrics_every": 0})
    rng = np.random.default_rng(a.seed)
    mu = max(1, a.population // 4)
    weights = np.log(mu + 0.5) - np.log(np.arange(1, mu + 1))
    weights /= weights.sum()
    mean = np.array([0.05, 7.5, 0.1])      # the controller's defaults
    sigma = 0.3 * (HIGH - LOW)             # per-gene step size
    best, best_fitness = mean.copy(), evaluate(sim, mean, seed=1)
    print(f"start: {dict(zip(NAMES, mean.round(3)))} coverage {best_fitness:.3f}")
    for generation in range(a.generations):
        seed = generation + 1
        offspring = np.clip(mean + sigma * rng.standard_normal((a.population, len(NAMES))),
                            LOW, HIGH)
        fitness = np.array([evaluate(sim, g, seed) for g in offspring])
        order = np.argsort(-fitness, kind="stable")
        mean = weights @ offspring[order[:mu]]
        sigma *= 0.9                       # anneal the steps
        if fitness[order[0]] > best_fitness:
            best, best_fitness = offspring[order[0]], fitness[order[0]]
        print(f"generation {generation + 1:2d}: best {fitness[order[0]]:.3f}, "
              f"mean {fitness.mean():.3f}, mean genome {dict(zip(NAMES, mean.round(3)))}")
    print(f"best: {dict(zip(NAMES, np.round(best, 3)))} coverage {best_fitness:.3f} "
          f"({a.generations} generations x {a.population} individuals, "
          f"{a.generations * a.population + 1} runs in one process)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

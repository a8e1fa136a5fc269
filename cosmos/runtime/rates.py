"""The two rates of the seed's two-level architecture (section 3) and the log rate.

Defaults, and why:

* ``servo_hz = 1000``: the servo level closes the force and motion loops. The
  physics steps at 1 ms, so a 1 kHz servo applies a fresh torque every physics
  step; the stiffest loop (force control against a table whose contact
  stiffness is ~1e5..1e6 N/m) needs that rate to stay well damped.
* ``param_hz = 125``: the parameter-evaluation level recomputes J, Lambda, mu,
  p and g (Pinocchio's computeAllTerms and two compiled calls: about 30 us per
  evaluation measured alone, 45-60 us inside the servo loop). The seed paces
  it "by the rate of configuration changes": at the joint speeds of these tasks
  (< 1 rad/s) the configuration moves < 8 mrad between evaluations and the
  operational position estimator ``x = x_e + J (q - q_e)`` covers the gap.
  Measured: a 0.4 m line at 0.25 m/s is tracked to 0.60 mm with evaluations at
  200 Hz and 0.61 mm at every 1 kHz tick (tests/runtime), and the decoupling,
  contact and insertion tests pass unchanged at 125 Hz; an eighth of the servo
  rate cuts the dynamics' cost per tick eightfold.
* ``state_hz = 250``: ``/cosmos/state`` is written at this fixed rate of
  simulated time (interfaces.md asks for at least 100 Hz).

The seed's own PUMA rates (225 Hz servo, 100 Hz evaluation) run too: the servo
then holds its torque across several 1 ms physics steps (zero-order hold).
"""

from __future__ import annotations

from dataclasses import dataclass

from cosmos.errors import UsageError

PHYSICS_HZ = 1000.0


@dataclass(frozen=True)
class Rates:
    """Servo, parameter-evaluation and log rates [Hz] of simulated time."""

    servo_hz: float = 1000.0
    param_hz: float = 125.0
    state_hz: float = 250.0

    def __post_init__(self) -> None:
        if not 0 < self.servo_hz <= PHYSICS_HZ:
            raise UsageError(
                f"--servo-hz must be in (0, {PHYSICS_HZ:g}] (the physics steps at "
                f"{PHYSICS_HZ:g} Hz); got {self.servo_hz:g}"
            )
        if not 0 < self.param_hz <= self.servo_hz:
            raise UsageError(
                f"--param-hz must be in (0, servo rate {self.servo_hz:g}]; got {self.param_hz:g}"
            )
        if not 100 <= self.state_hz <= PHYSICS_HZ:
            raise UsageError(f"state rate must be in [100, {PHYSICS_HZ:g}] Hz")

    @classmethod
    def chosen(cls, servo_hz: float | None, param_hz: float | None) -> Rates:
        """The rates a run asks for, defaults where it says nothing (``cosmos run``, ``cosmos.run``).

        The parameter rate defaults to the default's, but never faster than the servo.
        """
        defaults = cls()
        servo = defaults.servo_hz if servo_hz is None else servo_hz
        param = min(defaults.param_hz, servo) if param_hz is None else param_hz
        return cls(servo_hz=servo, param_hz=param, state_hz=defaults.state_hz)

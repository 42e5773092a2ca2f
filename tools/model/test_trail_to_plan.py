#!/usr/bin/env python3
"""Tests of trail_to_plan.py (run by `make model`): a trail's faults and commands become a plan's entries at
the times of the jobs the model's rounds stand for."""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import trail_to_plan  # noqa: E402

TRAIL = """\
          MODEL deliver job=0 round=0 tag=0 mode=0
          MODEL event command_taken round=1 code=1
          MODEL event tmr_established round=4 job=2
          MODEL event command_taken round=5 code=2
      MODEL fault round=6 kind=1 replica=255
 219:	proc  0 (:init::1) tmr.pml:1084 (state 151)	[printf('MODEL fault round=%d kind=%d replica=%d\\n',rnd,f,p)]
      MODEL fault round=7 kind=5 replica=2
spin: text of failed assertion: assert(0)
"""


class TrailToPlan(unittest.TestCase):
    def test_parse_keeps_each_event_once_in_order(self):
        faults, commands = trail_to_plan.parse(TRAIL.splitlines())
        self.assertEqual(faults, [(6, 1, 255), (7, 5, 2)])
        self.assertEqual(commands, [(1, 1), (5, 2)])

    def test_commands_are_sent_a_job_before_the_job_that_takes_them(self):
        text = trail_to_plan.plan(TRAIL.splitlines(), "t")
        self.assertIn('[[command]]\nt_s = 5.000000\nname = "filter_tmr"', text)
        self.assertIn('[[command]]\nt_s = 5.040000\nname = "filter_simplex"', text)

    def test_faults_land_in_their_jobs_period_before_the_filter_runs(self):
        text = trail_to_plan.plan(TRAIL.splitlines(), "t")
        # round 6 is job 506: its period starts at 5.06 s
        self.assertIn('[[fault]]\nt_s = 5.0605000\nkind = "core_hang"\nrole = "filter"\n', text)
        self.assertIn('t_s = 5.0705000\nkind = "sdc"\nrole = "filter_replica"\ninstance = 2\n'
                      'point = "nav_output"\nbit = 70', text)

    def test_a_reset_after_the_voters_job_lands_after_its_end(self):
        lines = ["MODEL event command_taken round=1 code=1", "MODEL fault round=8 kind=10 replica=255"]
        self.assertIn("t_s = 5.0811000\nkind = \"core_reset\"\nrole = \"filter\"",
                      trail_to_plan.plan(lines, "t"))

    def test_a_trail_without_the_switch_is_refused(self):
        with self.assertRaises(ValueError):
            trail_to_plan.plan(["MODEL fault round=3 kind=1 replica=255"], "t")

    def test_a_replica_fault_without_a_replica_is_refused(self):
        with self.assertRaises(ValueError):
            trail_to_plan.plan(["MODEL event command_taken round=1 code=1", "MODEL fault round=3 kind=3 replica=255"], "t")


if __name__ == "__main__":
    unittest.main()

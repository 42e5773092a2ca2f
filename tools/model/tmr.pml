/*
 * @file tmr.pml
 * @brief The filter's TMR protocol in Promela, checked by SPIN (docs/MODEL.md): the voter (fan-out
 *        of the job records, the vote, exclusion, re-seeding, the switch to TMR and back, its place
 *        in DDR and its restart), three replicas, the telecommands, and the injector's faults on
 *        those roles, within a bounded number of jobs and faults.
 *
 * Time goes in releases of 10 ms (a "round"): in each round the voter runs one job and each replica
 * one pass, in any order (the model does not fix the tiles' phase). Each step stands for the C++
 * named beside it; the names are those of trn/tasks/filter/filter_task.cpp (voter),
 * trn/tasks/filter/filter_tmr.cpp (replica) and fdir/tmr.cpp (vote, counts).
 *
 * Data are abstracted to tags: a record's content is a function of its job; a replica's state is
 * right (tag 0) or wrong (tag = the fault that made it so); an output carries its state's tag and a
 * "bad" bit when it fails the CRC its replica took (an sdc on nav_output). Two outputs agree when
 * their jobs and tags are equal and neither is bad (tmr_same over solution and digest).
 *
 * Compile-time options (check.sh passes them with -D):
 *   HORIZON      rounds flown (jobs 0 .. HORIZON-1)
 *   MAXF         faults injected at most
 *   FAULT_LAST   last round a fault may start at
 *   CMD_STOP     1: the ground may also send filter_simplex (at any round up to FAULT_LAST)
 *   CMD_RETMR    1: after a reported simplex the supervisor may command TMR once more
 *   MIDJOB       1: the voter may also be reset inside its job, after a delivery and before it
 *                writes its place in DDR (persist_voter), and boot in the same release or the next
 *   LATEJOB      1: the voter may also be reset after its job and boot in the same release (a boot
 *                takes 1 ms of the 10): it runs the same job again
 *   STOPPING_VOTER_FAULTS 0: no fault of the voter while it stops (finding F1, docs/MODEL.md)
 *   NO_REPLICA_FAULTS, NO_VOTER_FAULTS: restrict the fault space (a check of one path)
 *   MUTANT_*     seeded protocol errors; each must be found (check.sh)
 */

#ifndef HORIZON
#define HORIZON 20
#endif
#ifndef MAXF
#define MAXF 1
#endif
#ifndef FAULT_LAST
#define FAULT_LAST 8
#endif
#ifndef CMD_STOP
#define CMD_STOP 0
#endif
#ifndef CMD_RETMR
#define CMD_RETMR 0
#endif
#ifndef MIDJOB
#define MIDJOB 0
#endif
#ifndef LATEJOB
#define LATEJOB 0
#endif
#ifndef STOPPING_VOTER_FAULTS
#define STOPPING_VOTER_FAULTS 1
#endif
#ifndef FAULT_FIRST
#define FAULT_FIRST 2
#endif
/* Properties checked (1) or left out (0) of a run; docs/MODEL.md names them P1..P7. */
#ifndef P_NODUP
#define P_NODUP 1
#endif
#ifndef P_AGREED
#define P_AGREED 1
#endif
#ifndef P_RIGHT
#define P_RIGHT 1
#endif
#ifndef P_NOSKIP
#define P_NOSKIP 1
#endif
#ifndef P_RECOVER
#define P_RECOVER 1
#endif
#ifndef P_LATE
#define P_LATE 1
#endif
#ifndef P_SWITCH
#define P_SWITCH 1
#endif
/* Rounds the voter may be late with a delivery in TMR (J - d for job d delivered at job J). */
#ifndef LATE_MAX
#define LATE_MAX 8
#endif
/* Rounds a switch (Starting, Stopping) may take. */
#ifndef SWITCH_MAX
#define SWITCH_MAX 12
#endif
/* Rounds after the last fault or command by which the group is back (P5). */
#ifndef RECOVERY
#define RECOVERY 12
#endif

/* ---- constants of the C++ (names as there) */
#define NR 3                 /* kReplicas */
#define NONE 3               /* kNoReplica */
#define VOTE_LAG 2           /* kVoteLag */
#define OUT_RING 8           /* kOutRing: outputs the voter keeps per replica */
#define HELD_OUT 8           /* kHeldOutputs: outputs each replica keeps in DDR */
#define HELLO_EVERY 2        /* kHelloEvery */
#define JOBS_PER_REL 2       /* kReplicaJobsPerRelease */
#define DISAGREE_X 2         /* TmrGroupConfig::disagree_to_exclude */
#define MISS_X 3             /* TmrGroupConfig::miss_to_exclude */
#define NOMAJ_FALLBACK 2     /* kNoMajorityToFallBack */
#define VOTES_PER_JOB 4      /* kVotesPerJob */
#define MAX_REJOIN 24        /* kMaxRejoinGap */
#define CK_EVERY 10          /* FilterTaskConfig::checkpoint_every */
/* kStartJobs is 100 (1 s): the model gives up sooner, so that the give-up falls inside its horizon */
#ifndef START_JOBS
#define START_JOBS 6
#endif
#define VOTER_BIT 8          /* kVoterBit */
#define ALL_REPLICAS 7       /* kTmrAllReplicas */

#define SIMPLEX 0
#define STARTING 1
#define TMR 2
#define STOPPING 3

#define BAD 128              /* an output that fails its replica's CRC */
#define STALE 100            /* the voter ran a record on a state that was not the one before it */
#define CATCHUP 254          /* resumed from a checkpoint: the next record brings it up to date */
#define UNSET 253            /* no state that belongs to the stream (set_up before rejoin) */

#define NJ (HORIZON + 2)
#define BIT(i) (1 << (i))
#define HAS(m, i) (((m) >> (i)) & 1)
#define POP3(m) (HAS(m, 0) + HAS(m, 1) + HAS(m, 2))

/* ---- what the injector does (FAULT_PLANS.md kinds), as the model names them */
#define F_NONE 0
#define F_V_HANG 1           /* core_hang, role filter */
#define F_V_RESET 2          /* core_reset, role filter */
#define F_R_HANG 3           /* core_hang, role filter_replica */
#define F_R_RESET 4          /* core_reset, role filter_replica */
#define F_R_BADOUT 5         /* sdc at nav_output of a replica: its next output fails its CRC */
#define F_R_STATE 6          /* seu in a replica's ekf carve / sdc at filter_state: its digest differs */
#define F_R_REFUSE 7         /* a replica's state its own checks refuse (far upset, settings upset) */
#define F_V_MIDJOB 8         /* core_reset of the voter between a delivery and the write of its place */
#define F_R_MIDJOB 9         /* core_reset of a replica after it sent an output, before after_job */
#define F_V_LATE 10          /* core_reset of the voter after its job, booted again in the same release */

/* ================================================================ shared: DDR (TmrArea, CheckpointArea) */
/* TmrControl */
byte ctl_mode; byte ctl_epoch; byte ctl_seed_by = NONE; byte ctl_seed_job; byte ctl_seed_for;
byte ctl_ckpt_by = NONE; byte ctl_gen[NR];
/* TmrSeed (its CRC taken as good: a torn seed is refused like a missing one) */
byte seed_serial; byte seed_job; byte seed_for; byte seed_epoch; byte seed_gen[NR]; byte seed_tag;
/* ring of job records: written or not (the horizon is shorter than kJobRingLen = 32) */
bit ring_w[NJ];
/* TmrArea::outputs: each replica's last outputs, slot job % HELD_OUT: job + 1 (0: none), tag | BAD */
byte kept_job[NR * HELD_OUT]; byte kept_val[NR * HELD_OUT];
/* TmrVoter: the voter's place (pl_valid: serial != 0 and CRC good) */
bit pl_valid; byte pl_epoch; bit pl_voting; byte pl_record_job; byte pl_next_vote; byte pl_next_deliver;
bit pl_delivered_any; byte pl_active; byte pl_last_winner; byte pl_vck_seq[2]; byte pl_vck_dig[2];
/* CheckpointArea: two slots, seq (0: none), the state's tag, the digest it was written with (0: none) */
byte ck_seq[2]; byte ck_tag[2]; byte ck_dig[2];

/* ================================================================ the voter's tile RAM (TaskState) */
byte v_mode;
byte v_next_deliver; bit v_delivered_any; byte v_start_job;
byte v_active;                                   /* TmrGroup::active_ */
byte v_dis_row[NR]; byte v_miss_row[NR];         /* TmrReplicaCount: in a row */
byte v_out_job[NR * OUT_RING]; byte v_out_val[NR * OUT_RING];  /* TaskState::out, out_bad */
byte v_own_job[OUT_RING]; byte v_own_val[OUT_RING];            /* TaskState::own */
byte v_hello; byte v_refused; byte v_seeded_differ[NR]; byte v_seed_asked;
bit v_resume_tmr; byte v_last_winner; byte v_nomaj_run;
byte v_vck_seq[2]; byte v_vck_dig[2];             /* voted_ckpt */
byte v_stop_job; bit v_stop_voted; byte v_stop_digest; bit v_stop_again;
byte v_next_vote; bit v_rejoin; byte v_rebuild_from; byte v_lenient_until;
byte v_own_tag; byte v_own_pos;                  /* the voter's own filter state */
bit v_catching_up; byte v_ckslot;
byte v_cmd;                                      /* TaskState::command, this job */

/* ================================================================ the replicas' tile RAM (Replica) */
bit r_seeded[NR]; byte r_epoch[NR]; byte r_gen[NR]; byte r_seed_serial[NR]; byte r_next_job[NR];
byte r_since_hello[NR]; byte r_tag[NR]; byte r_ckslot[NR];

/* Messages on kChanNav to the voter (kMsgReplicaOut, kMsgReplicaHello) are written where the voter's
 * drain_replicas() would put them (its out ring, its hello and refused masks): a message that comes
 * before the voter's job is taken by it, one after by its next job, whatever their order. */

/* ================================================================ the board and the injector */
byte rnd;                          /* the release: job number of the round */
bit done[4];                       /* 0 voter, 1..3 replicas: stepped this round */
byte down[4];                      /* rounds it stays hung or booting */
bit restart[4];                    /* its RAM was emptied: it starts afresh at its next step */
bit go;                            /* the round is open */
byte nfaults;
byte pend_badout[NR];              /* an sdc at nav_output waits for the replica's next output */
byte pend_state[NR];               /* 1: wrong state (digest), 2: refused by its checks */
byte cmd_pending;                  /* telecommand up: 1 filter_tmr, 2 filter_simplex */
byte midjob_armed;                 /* F_V_MIDJOB / F_R_MIDJOB aimed at the voter (1) or replica i (2 + i) */

/* ================================================================ ghosts: what the properties read */
bit g_deliv[NJ];                   /* job delivered */
byte g_agree[NJ];                  /* replicas that sent a good right output of the job */
bit g_simplex_reported = 1;        /* simplex and said so (tmr_simplex), or never in TMR */
byte g_switch_since;               /* round the voter entered Starting or Stopping */
byte g_last_event;                 /* round of the last fault or command */
byte g_cmd_taken;                  /* commands taken by the voter */

/* ================================================================ helpers */
/* fdir::tmr_same over two kept outputs: same job, same tag, neither bad (bad ones never win) */
#define AGREE(a, b) ((a) == (b) && ((a) & BAD) == 0)

/* Delivery (filter_task.cpp deliver): publishes and sends job j's solution if it is the next due,
 * never twice, never back. The ghosts check P1 (no job twice) and P3 (no wrong solution). */
inline deliver(j, val) {
  if
  :: (v_delivered_any && j < v_next_deliver) -> skip   /* delivered already */
  :: else ->
     printf("MODEL deliver job=%d round=%d tag=%d mode=%d\n", j, rnd, val, v_mode);
     assert(!P_NODUP || !g_deliv[j]);                   /* P1 no job delivered twice */
     assert(!P_RIGHT || val == 0);                      /* P3 no wrong solution delivered */
     g_deliv[j] = 1;
     v_delivered_any = 1;
     v_next_deliver = j + 1
  fi
}

/* run_own (filter_task.cpp): the voter's own filter runs record j. */
inline run_own(j, outv) {
  if
  :: v_own_pos == CATCHUP -> skip                      /* catch_up(): samples since the checkpoint replayed */
  :: v_own_pos != CATCHUP && v_own_pos + 1 != j -> v_own_tag = STALE
  :: else -> skip
  fi;
  v_own_pos = j;
  outv = v_own_tag
}

/* checkpoint_write from the voter (simplex checkpoint()) or a replica (after_job()). */
inline ck_write(slot, job, tag, dig) {
  slot = 1 - slot;
  ck_seq[slot] = job / CK_EVERY + 1;
  ck_tag[slot] = tag;
  ck_dig[slot] = dig
}

/* The voter's RAM emptied (reset): TaskState value-initialised. */
inline voter_ram_clear() {
  v_mode = SIMPLEX; v_next_deliver = 0; v_delivered_any = 0; v_start_job = 0; v_active = 0;
  k = 0;
  do
  :: k < NR -> v_dis_row[k] = 0; v_miss_row[k] = 0; v_seeded_differ[k] = 0; k++
  :: else -> break
  od;
  k = 0;
  do
  :: k < NR * OUT_RING -> v_out_job[k] = 0; v_out_val[k] = 0; k++
  :: else -> break
  od;
  k = 0;
  do
  :: k < OUT_RING -> v_own_job[k] = 0; v_own_val[k] = 0; k++
  :: else -> break
  od;
  v_hello = 0; v_refused = 0; v_seed_asked = 0; v_resume_tmr = 0; v_last_winner = 0; v_nomaj_run = 0;
  v_vck_seq[0] = 0; v_vck_seq[1] = 0; v_vck_dig[0] = 0; v_vck_dig[1] = 0;
  v_stop_job = 0; v_stop_voted = 0; v_stop_digest = 0; v_stop_again = 0; v_next_vote = 0; v_rejoin = 0;
  v_rebuild_from = 0; v_lenient_until = 0; v_own_tag = 0; v_own_pos = UNSET; v_catching_up = 0;
  v_ckslot = 0; v_cmd = 0                      /* the endpoint's queue was in its RAM too */
}

/* resume_from_checkpoint (filter_task.cpp): the newest good checkpoint; with `voted`, only one whose
 * (seq, digest) the vote confirmed. found = 1 if restored. */
inline resume_ck(voted, found) {
  found = 0;
  k = (ck_seq[1] > ck_seq[0] -> 1 : 0);
  n = 0;
  do
  :: n < 2 && !found ->
     if
     :: ck_seq[k] != 0 && (!voted || (v_vck_seq[0] == ck_seq[k] && v_vck_dig[0] == ck_dig[k] && ck_dig[k] != 0)
                           || (v_vck_seq[1] == ck_seq[k] && v_vck_dig[1] == ck_dig[k] && ck_dig[k] != 0)) ->
        found = 1;
        v_own_tag = ck_tag[k];
        v_own_pos = CATCHUP;
        v_catching_up = 1;
        v_ckslot = k
     :: else -> k = 1 - k
     fi;
     n++
  :: else -> break
  od
}

/* ================================================================ the voter (filter_task.cpp) */

/* take_place + rejoin: a voter restarted while it voted goes on from its place in DDR. */
inline rejoin(ok) {
  ok = 0;
  if
  :: pl_valid && pl_voting && pl_epoch == ctl_epoch && rnd > pl_record_job && rnd - pl_record_job <= MAX_REJOIN ->
     ok = 1;
     v_mode = TMR;                                     /* take_place */
     v_next_vote = pl_next_vote;
     v_next_deliver = pl_next_deliver;
     v_delivered_any = pl_delivered_any;
     v_last_winner = pl_last_winner;
     v_vck_seq[0] = pl_vck_seq[0]; v_vck_seq[1] = pl_vck_seq[1];
     v_vck_dig[0] = pl_vck_dig[0]; v_vck_dig[1] = pl_vck_dig[1];
     v_active = pl_active;                             /* group.configure, then admit each voting */
     /* the outputs the replicas kept for the jobs it had not voted (keep_kept_output) */
     i = 0;
     do
     :: i < NR ->
        j = pl_next_vote;
        do
        :: j <= pl_record_job && j - pl_next_vote < HELD_OUT ->
           if
           :: kept_job[i * HELD_OUT + j % HELD_OUT] == j + 1 ->
              v_out_job[i * OUT_RING + j % OUT_RING] = j + 1;
              v_out_val[i * OUT_RING + j % OUT_RING] = kept_val[i * HELD_OUT + j % HELD_OUT]
           :: else -> skip
           fi;
           j++
        :: else -> break
        od;
        i++
     :: else -> break
     od;
     v_catching_up = 1;
     v_rejoin = 1;
     v_rebuild_from = pl_record_job + 1;
     v_lenient_until = rnd + (rnd - pl_record_job) + VOTE_LAG + 4;
     printf("MODEL event tmr_voter_resumed round=%d next_deliver=%d\n", rnd, pl_next_deliver)
  :: else -> skip
  fi
}

/* set_up (filter_task.cpp): at the task's start, after a reset or on a spare. */
inline voter_set_up() {
  voter_ram_clear();
  if
  :: ctl_mode != 0 ->
     rejoin(ok);
     if
     :: ok -> skip                                      /* it votes: its own filter waits */
     :: else ->
        ctl_mode = 0;                                   /* not voting when it stopped, or out too long */
        v_resume_tmr = 1;
        g_simplex_reported = 1;
        g_switch_since = 0;
        printf("MODEL event tmr_simplex round=%d cause=restart\n", rnd)
     fi
  :: else -> ok = 0
  fi;
  if
  :: !ok ->
     resume_ck(0, found);                               /* a checkpoint left by an earlier start */
     if
     :: !found -> v_own_tag = 0; v_own_pos = CATCHUP    /* ekf->init from the initial estimate */
     :: else -> skip
     fi
  :: else -> skip
  fi
}

/* rebuild (filter_task.cpp): after a rejoin, the records of the jobs it missed. */
inline rebuild() {
  if
  :: v_rejoin ->
     v_rejoin = 0;
     j = v_rebuild_from;
     do
     :: j < rnd && rnd - j <= MAX_REJOIN -> ring_w[j] = 1; j++
     :: else -> break
     od
  :: else -> skip
  fi
}

/* start_tmr (filter_task.cpp): the voter's state after this job is the replicas' seed. */
inline start_tmr() {
  ctl_epoch++;
  ctl_mode = 1;
  ctl_seed_by = NONE;
  ctl_ckpt_by = NONE;
  /* tmr_write_seed(all replicas) */
  seed_job = rnd; seed_for = ALL_REPLICAS; seed_epoch = ctl_epoch; seed_tag = v_own_tag;
  seed_gen[0] = ctl_gen[0]; seed_gen[1] = ctl_gen[1]; seed_gen[2] = ctl_gen[2];
  seed_serial++;
  v_active = 0;                                          /* group.configure */
  k = 0;
  do
  :: k < NR -> v_dis_row[k] = 0; v_miss_row[k] = 0; v_seeded_differ[k] = 0; k++
  :: else -> break
  od;
  v_mode = STARTING;
  v_start_job = rnd;
  v_hello = 0; v_refused = 0; v_seed_asked = 0; v_nomaj_run = 0;
  v_vck_seq[0] = 0; v_vck_seq[1] = 0; v_vck_dig[0] = 0; v_vck_dig[1] = 0;
  g_simplex_reported = 0;
  g_switch_since = rnd;
  printf("MODEL event tmr_starting round=%d epoch=%d\n", rnd, ctl_epoch)
}

/* stop_tmr (filter_task.cpp): back to simplex, replicas idle, reported (tmr_simplex). */
inline stop_tmr() {
  ctl_mode = 0;
  v_mode = SIMPLEX;
  g_simplex_reported = 1;
  g_switch_since = 0;
  printf("MODEL event tmr_simplex round=%d\n", rnd)
}

/* compare_starting (filter_task.cpp): a replica whose output equals the voter's own joins. */
inline compare_starting(v) {
  if
  :: v_own_job[v % OUT_RING] == v + 1 ->
     i = 0;
     do
     :: i < NR ->
        if
        :: v_out_job[i * OUT_RING + v % OUT_RING] == v + 1 &&
           AGREE(v_out_val[i * OUT_RING + v % OUT_RING], v_own_val[v % OUT_RING]) && !HAS(v_active, i) ->
           v_active = v_active | BIT(i); v_dis_row[i] = 0; v_miss_row[i] = 0   /* group.admit */
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     if
     :: v_active == ALL_REPLICAS ->
        v_mode = TMR;
        v_next_vote = v + 1;                             /* delivered already, by its own filter */
        ctl_ckpt_by = 0;
        g_switch_since = 0;
        printf("MODEL event tmr_established round=%d job=%d\n", rnd, v)
     :: else ->
        if
        :: rnd - v_start_job > START_JOBS -> stop_tmr()
        :: else -> skip
        fi
     fi
  :: else -> skip
  fi
}

/* fall_back (filter_task.cpp): two votes without a majority; alone from a voted checkpoint. */
inline fall_back(v) {
  resume_ck(1, found);
  if
  :: found ->
     stop_tmr();
     v_nomaj_run = 0;
     printf("MODEL event tmr_fallback round=%d job=%d\n", rnd, v)
  :: else -> skip                                         /* none: it keeps voting */
  fi
}

/* vote (filter_task.cpp) with fdir::tmr_vote and TmrGroup::account (fdir/tmr.cpp). */
inline vote(d) {
  /* tmr_vote: good records of the expected replicas; the first that agrees with another wins */
  present = 0; badm = 0; winner = NONE;
  i = 0;
  do
  :: i < NR ->
     if
     :: HAS(v_active, i) && v_out_job[i * OUT_RING + d % OUT_RING] == d + 1 ->
        if
        :: (v_out_val[i * OUT_RING + d % OUT_RING] & BAD) != 0 -> badm = badm | BIT(i)
        :: else -> present = present | BIT(i)
        fi
     :: else -> skip
     fi;
     i++
  :: else -> break
  od;
  missing = v_active & ~(present | badm) & ALL_REPLICAS;
  i = 0;
  do
  :: i < NR && winner == NONE ->
     j = i + 1;
     do
     :: j < NR ->
        if
        :: winner == NONE && HAS(present, i) && HAS(present, j) &&
           v_out_val[i * OUT_RING + d % OUT_RING] == v_out_val[j * OUT_RING + d % OUT_RING] -> winner = i
        :: else -> skip
        fi;
        j++
     :: else -> break
     od;
     i++
  :: else -> break
  od;
#ifdef MUTANT_DELIVER_EARLY
  /* seeded error: the first good output in is delivered, before a second one has confirmed it */
  winner = (HAS(present, 0) -> 0 : (HAS(present, 1) -> 1 : (HAS(present, 2) -> 2 : NONE)));
#endif
  if
  :: winner == NONE ->                                   /* kNoMajority: nothing delivered */
     v_nomaj_run++;
     printf("MODEL event tmr_no_majority round=%d job=%d\n", rnd, d);
     if
     :: v_nomaj_run >= NOMAJ_FALLBACK -> fall_back(d)
     :: else -> skip
     fi
  :: else ->
     wval = v_out_val[winner * OUT_RING + d % OUT_RING];
     differ = badm;
     i = 0;
     do
     :: i < NR ->
        if
        :: HAS(present, i) && v_out_val[i * OUT_RING + d % OUT_RING] != wval -> differ = differ | BIT(i)
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     v_nomaj_run = 0;
     /* account_vote / TmrGroup::account: counts in a row, exclusion raises the replica's generation */
     excl = 0;
     i = 0;
     do
     :: i < NR ->
        if
        :: HAS(v_active, i) ->
           if
           :: HAS(differ, i) -> v_dis_row[i]++
           :: !HAS(differ, i) && !HAS(missing, i) -> v_dis_row[i] = 0
           :: else -> skip
           fi;
           if
           :: HAS(missing, i) -> v_miss_row[i]++
           :: else -> v_miss_row[i] = 0
           fi;
           if
           :: v_dis_row[i] >= DISAGREE_X || v_miss_row[i] >= MISS_X -> excl = excl | BIT(i)
           :: else -> skip
           fi
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     i = 0;
     do
     :: i < NR ->
        if
        :: HAS(excl, i) ->
           v_active = v_active & ~BIT(i) & ALL_REPLICAS;
           ctl_gen[i]++;                                 /* it drops its state and waits for a seed */
           printf("MODEL event tmr_excluded round=%d replica=%d\n", rnd, i)
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     /* readmit: a replica not voting whose output equals the vote is readmitted */
     i = 0;
     do
     :: i < NR ->
        if
        :: !HAS(v_active, i) && v_out_job[i * OUT_RING + d % OUT_RING] == d + 1 ->
           if
           :: AGREE(v_out_val[i * OUT_RING + d % OUT_RING], wval) ->
              v_active = v_active | BIT(i); v_dis_row[i] = 0; v_miss_row[i] = 0;
              v_hello = v_hello & ~BIT(i); v_refused = v_refused & ~BIT(i); v_seeded_differ[i] = 0;
              printf("MODEL event tmr_resynced round=%d replica=%d\n", rnd, i)
           :: else ->
              v_seeded_differ[i]++;
              if
              :: v_seeded_differ[i] >= OUT_RING -> v_seeded_differ[i] = 0; ctl_gen[i]++
              :: else -> skip
              fi
           fi
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     /* P2: a solution delivered in TMR is agreed by at least two replicas */
     agreeing = 0;
     i = 0;
     do
     :: i < NR ->
        if
        :: v_out_job[i * OUT_RING + d % OUT_RING] == d + 1 && AGREE(v_out_val[i * OUT_RING + d % OUT_RING], wval) ->
           agreeing++
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     assert(!P_AGREED || agreeing >= 2);
     deliver(d, wval);
#if MIDJOB
     if
     :: midjob_armed == 1 -> goto voter_reset_midjob    /* between the delivery and persist_voter */
     :: else -> skip
     fi;
#endif
     /* note_voted_checkpoint */
     if
     :: d % CK_EVERY == 0 -> v_vck_seq[(d / CK_EVERY) % 2] = d / CK_EVERY + 1; v_vck_dig[(d / CK_EVERY) % 2] = wval + 1
     :: else -> skip
     fi;
     v_last_winner = winner;
     if
     :: v_mode == STOPPING && d == v_stop_job -> v_stop_voted = 1; v_stop_digest = wval
     :: else -> skip
     fi;
     if
     :: v_mode != STOPPING ->
        /* a replica that asked for a seed gets one from the voted state */
        waiting = v_hello & ~v_active & ALL_REPLICAS;
        if
        :: waiting != 0 && (v_seed_asked == 0 || v_seed_asked > OUT_RING) ->
           ctl_seed_for = waiting; ctl_seed_job = rnd; ctl_seed_by = winner;
           v_seed_asked = 1; v_hello = 0
        :: else ->
           if
           :: v_seed_asked != 0 && v_seed_asked <= OUT_RING -> v_seed_asked++
           :: else -> skip
           fi
        fi;
        if
        :: ctl_ckpt_by >= NR || !HAS(v_active, ctl_ckpt_by) -> ctl_ckpt_by = winner
        :: else -> skip
        fi
     :: else -> skip
     fi
  fi
}

/* vote_due (filter_task.cpp): job v alone, or up to VOTES_PER_JOB older ones after a restart. */
inline vote_due(v) {
  if
  :: v_next_vote + OUT_RING / 2 < v -> v_next_vote = v - OUT_RING / 2   /* older outputs gone */
  :: else -> skip
  fi;
  nv = 0;
  do
  :: nv < VOTES_PER_JOB && v_next_vote <= v && v_mode != SIMPLEX ->
     d = v_next_vote;
     /* fill_from_ddr: outputs that did not come over the network, from the replicas' DDR copies */
     i = 0;
     do
     :: i < NR ->
        if
        :: HAS(v_active, i) && v_out_job[i * OUT_RING + d % OUT_RING] != d + 1 &&
           kept_job[i * HELD_OUT + d % HELD_OUT] == d + 1 ->
           v_out_job[i * OUT_RING + d % OUT_RING] = d + 1;
           v_out_val[i * OUT_RING + d % OUT_RING] = kept_val[i * HELD_OUT + d % HELD_OUT]
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
     /* all_present: until lenient_until a vote waits for every voting replica's output */
     allp = 1;
     i = 0;
     do
     :: i < NR ->
        if
        :: HAS(v_active, i) && v_out_job[i * OUT_RING + d % OUT_RING] != d + 1 -> allp = 0
        :: else -> skip
        fi;
        i++
     :: else -> break
     od;
#ifdef MUTANT_WAIT_FOREVER
     /* seeded error: a vote always waits for every voting replica's output (no lenient_until) */
     if
     :: !allp -> break
     :: else -> skip
     fi;
#endif
     if
     :: rnd < v_lenient_until && !allp -> break
     :: else -> skip
     fi;
     vote(d);
     v_next_vote = d + 1;
     nv++
  :: else -> break
  od
}

/* begin_stop (filter_task.cpp): the replica that agreed with the last vote saves its state. */
inline begin_stop() {
  ctl_seed_for = VOTER_BIT;
  ctl_seed_job = rnd;
  ctl_seed_by = v_last_winner;
  v_stop_job = rnd;
  v_stop_voted = 0;
  v_stop_again = 0;
  if
  :: v_mode != STOPPING -> g_switch_since = rnd
  :: else -> skip
  fi;
  v_mode = STOPPING
}

/* finish_stop (filter_task.cpp): the voted state after the stop job, then the records since. */
inline finish_stop(v) {
  if
  :: v >= v_stop_job ->
     if
     :: v_stop_voted && seed_job == v_stop_job && (seed_for & VOTER_BIT) && seed_epoch == ctl_epoch &&
        seed_serial != 0 && seed_tag == v_stop_digest ->
        v_own_tag = seed_tag;                            /* core_load */
        v_own_pos = v_stop_job;
#ifndef MUTANT_STOP_NO_REPLAY
        j = v_stop_job + 1;
        do
        :: j < rnd ->
           assert(ring_w[j]);                            /* record_ok: in the ring */
           run_own(j, outv);
           deliver(j, outv);
           j++
        :: else -> break
        od;
#endif
        run_own(rnd, outv);
        deliver(rnd, outv);
        stop_tmr()
     :: else ->
        v_stop_again = (rnd - v_stop_job >= OUT_RING)
     fi
  :: else -> skip
  fi
}

/* persist_voter (filter_task.cpp): the voter's place in the stream to DDR. */
inline persist_voter() {
  pl_valid = 1;
  pl_epoch = ctl_epoch;
  pl_voting = (v_mode == TMR);
  pl_record_job = rnd;
  pl_next_vote = v_next_vote;
  pl_next_deliver = v_next_deliver;
  pl_delivered_any = v_delivered_any;
  pl_active = v_active;
  pl_last_winner = v_last_winner;
  pl_vck_seq[0] = v_vck_seq[0]; pl_vck_seq[1] = v_vck_seq[1];
  pl_vck_dig[0] = v_vck_dig[0]; pl_vck_dig[1] = v_vck_dig[1]
}


proctype Voter() {
  byte i, j, k, n, d, v, nv, outv, wval, present, badm, missing, winner, differ, excl,
       waiting, agreeing;
  bit ok, found, allp;
end_voter:                                               /* waits for the next release: a valid end */
  do
  :: atomic {
     go && !done[0] && down[0] == 0 ->
     if
     :: restart[0] -> restart[0] = 0; voter_set_up()
     :: else -> skip
     fi;
     /* filter_task_main: one pass per release */
     v_cmd = cmd_pending; cmd_pending = 0;               /* consume_imu / take_command */
     if
     :: v_cmd != 0 -> g_cmd_taken++; printf("MODEL event command_taken round=%d code=%d\n", rnd, v_cmd)
     :: else -> skip
     fi;
     rebuild();
     if
     :: v_mode == SIMPLEX ->
        if
        :: v_catching_up && v_own_pos == CATCHUP -> v_catching_up = 0   /* catch_up: replay done */
        :: else -> skip
        fi;
        run_own(rnd, outv);                              /* run_checked: the simplex filter */
        deliver(rnd, outv);
        if
        :: rnd % CK_EVERY == 0 && !v_catching_up -> ck_write(v_ckslot, rnd, v_own_tag, 0)   /* checkpoint() */
        :: else -> skip
        fi;
        if
        :: v_cmd == 1 || (v_resume_tmr && !v_catching_up) -> v_resume_tmr = 0; start_tmr()
        :: else -> skip
        fi
     :: else ->
        if
        :: (v_cmd == 2 && v_mode == TMR) || (v_mode == STOPPING && v_stop_again) -> begin_stop()
        :: else -> skip
        fi;
        /* tmr_job: drain_replicas (the messages are in place already, see above) */
        v = (rnd >= VOTE_LAG -> rnd - VOTE_LAG : 0);
        if
        :: v_mode == TMR || v_mode == STOPPING -> vote_due(v)
        :: else -> skip
        fi;
        ring_w[rnd] = 1;                                 /* the record to the ring, after the control block */
        if
        :: v_mode == STARTING ->
           run_own(rnd, outv);
           v_own_job[rnd % OUT_RING] = rnd + 1; v_own_val[rnd % OUT_RING] = outv;
           deliver(rnd, outv);
           compare_starting(v)
        :: v_mode == STOPPING -> finish_stop(v)
        :: else -> skip
        fi;
        if
        :: v_mode != SIMPLEX -> persist_voter()
        :: else -> skip
        fi;
        if
        :: v_cmd == 2 && v_mode == STARTING -> stop_tmr()
        :: else -> skip
        fi
     fi;
     done[0] = 1;
#if LATEJOB
     if
     :: midjob_armed == 9 ->                             /* reset after its job: boots in this release */
        midjob_armed = 0;
        printf("MODEL fault round=%d kind=v_reset_late\n", rnd);
        restart[0] = 1;
        done[0] = 0
     :: else -> skip
     fi;
#endif
     goto voter_next;
#if MIDJOB
voter_reset_midjob:
     /* reset_tile_for: RAM emptied; it boots 1 ms later, in this release (the same job) or the next */
     printf("MODEL fault round=%d kind=v_reset_midjob\n", rnd);
     midjob_armed = 0;
     restart[0] = 1;
     if
     :: skip                                             /* same release: runs job rnd again */
     :: done[0] = 1                                      /* next release */
     fi;
#endif
voter_next:
     skip
  }
  od
}

/* ================================================================ a replica (filter_tmr.cpp) */

/* send_output: to the voter (kMsgReplicaOut) and kept in DDR. */
inline send_output(me, job) {
  if
  :: pend_badout[me] -> pend_badout[me] = 0; outv = r_tag[me] | BAD   /* sdc at nav_output: fails the CRC */
  :: else -> outv = r_tag[me]
  fi;
  if
  :: (outv & BAD) == 0 && outv == 0 -> g_agree[job] = g_agree[job] | BIT(me)
  :: else -> skip
  fi;
  kept_job[me * HELD_OUT + job % HELD_OUT] = job + 1;
  kept_val[me * HELD_OUT + job % HELD_OUT] = outv;
  if
  :: down[0] == 0 ->                                     /* take_replica_out, keep_output */
     v_out_job[me * OUT_RING + job % OUT_RING] = job + 1;
     v_out_val[me * OUT_RING + job % OUT_RING] = outv
  :: else -> skip                                        /* the voter's tile is down: lost */
  fi
}

inline send_hello(me, refused) {
  if
  :: down[0] == 0 ->                                     /* take_hello */
     v_hello = v_hello | BIT(me);
     if
     :: refused -> v_refused = v_refused | BIT(me)
     :: else -> skip
     fi
  :: else -> skip
  fi
}

proctype Replica(byte me) {
  byte n, job, outv;
  bit ok;
end_replica:
  do
  :: atomic {
     go && !done[me + 1] && down[me + 1] == 0 ->
     if
     :: restart[me + 1] ->                               /* RAM emptied: value-initialised */
        restart[me + 1] = 0;
        r_seeded[me] = 0; r_epoch[me] = 0; r_gen[me] = 0; r_seed_serial[me] = 0; r_next_job[me] = 0;
        r_since_hello[me] = 0; r_tag[me] = 0; r_ckslot[me] = 0; pend_state[me] = 0
     :: else -> skip
     fi;
     if
     :: ctl_mode == 0 -> r_seeded[me] = 0                /* the group does not run: idle */
     :: else ->
        if
        :: r_seeded[me] && (r_epoch[me] != ctl_epoch || r_gen[me] != ctl_gen[me]) -> r_seeded[me] = 0
        :: else -> skip
        fi;
        if
        :: !r_seeded[me] ->                               /* try_seed */
           if
           :: seed_serial != 0 && seed_serial != r_seed_serial[me] && (seed_for & BIT(me)) &&
              seed_epoch == ctl_epoch && seed_gen[me] == ctl_gen[me] ->
              r_seed_serial[me] = seed_serial;
              r_seeded[me] = 1; r_epoch[me] = seed_epoch; r_gen[me] = seed_gen[me];
              r_next_job[me] = seed_job + 1; r_tag[me] = seed_tag;
              pend_state[me] = 0                          /* the upset state is replaced */
           :: else -> skip
           fi
        :: else -> skip
        fi;
        if
        :: r_seeded[me] ->                                /* run_records */
           n = 0;
           do
           :: n < JOBS_PER_REL && r_seeded[me] && r_next_job[me] < NJ && ring_w[r_next_job[me]] ->
              job = r_next_job[me];
              /* core_run, then job_ok: an upset that struck before this job shows now */
              if
              :: pend_state[me] == 1 -> pend_state[me] = 0; r_tag[me] = 10 + me   /* digest differs from now on */
              :: pend_state[me] == 2 ->
                 pend_state[me] = 0;
                 r_seeded[me] = 0;                        /* refused by its own checks: drops its state */
                 send_hello(me, 1);
                 r_since_hello[me] = 0;
                 break
              :: else -> skip
              fi;
              send_output(me, job);
              if
              :: midjob_armed == 2 + me ->                /* reset before after_job: no seed, no checkpoint */
                 midjob_armed = 0;
                 printf("MODEL fault round=%d kind=r_reset_midjob replica=%d\n", rnd, me);
                 restart[me + 1] = 1;
                 down[me + 1] = 1;
                 break
              :: else -> skip
              fi;
              /* after_job: a seed asked of it, a checkpoint (with its digest) */
              if
              :: ctl_seed_by == me && ctl_seed_job == job ->
                 seed_job = job; seed_for = ctl_seed_for; seed_epoch = ctl_epoch; seed_tag = r_tag[me];
                 seed_gen[0] = ctl_gen[0]; seed_gen[1] = ctl_gen[1]; seed_gen[2] = ctl_gen[2];
                 seed_serial++
              :: else -> skip
              fi;
              if
              :: ctl_ckpt_by == me && job % CK_EVERY == 0 -> ck_write(r_ckslot[me], job, r_tag[me], r_tag[me] + 1)
              :: else -> skip
              fi;
              r_next_job[me]++;
              n++
           :: else -> break
           od
        :: else -> skip
        fi;
        if
        :: !r_seeded[me] && !restart[me + 1] ->
           r_since_hello[me]++;
           if
           :: r_since_hello[me] >= HELLO_EVERY -> r_since_hello[me] = 0; send_hello(me, 0)
           :: else -> skip
           fi
        :: else -> skip
        fi
     fi;
     done[me + 1] = 1
  }
  od
}

/* ================================================================ the board, the injector and the ground */

/* A hung tile: its watchdog (20 ticks) resets it 1 or 2 releases later; it boots in 1 ms. */
inline hang(p) {
  if
  :: down[p] = 1
  :: down[p] = 2
  :: down[p] = 3
  fi;
  restart[p] = 1
}

/* A crashed tile boots 1 ms later: it runs in this release or the next. */
inline crash(p) {
  restart[p] = 1;
  if
  :: down[p] = 0
  :: down[p] = 1
  fi
}

inline final_checks() {
  /* P4: no job skipped while two replicas agreed on it: every job below the last delivered one, and
   * every job whose delivery is more than LATE_MAX releases overdue at the end */
  k = 0;
  do
  :: k + 1 < v_next_deliver || k + VOTE_LAG + LATE_MAX < HORIZON ->
     if
     :: !g_deliv[k] ->
        printf("MODEL skipped job=%d agreed_by=%d\n", k, POP3(g_agree[k]));
        assert(!P_NOSKIP || POP3(g_agree[k]) < 2)
     :: else -> skip
     fi;
     k++
  :: else -> break
  od;
  /* P5: some time after the last fault or command, TMR with three voting, or a reported simplex */
  if
  :: g_last_event + RECOVERY <= HORIZON ->
     assert(!P_RECOVER || (v_mode == TMR && v_active == ALL_REPLICAS && ctl_mode == 1) ||
            (v_mode == SIMPLEX && g_simplex_reported && ctl_mode == 0))
  :: else -> skip
  fi
}

init {
  byte k, p, f;
  /* the checkpoint the simplex filter wrote at job 0 */
  ck_seq[1] = 1; ck_tag[1] = 0; ck_dig[1] = 0;
  v_own_pos = CATCHUP;
  atomic {
    run Voter();
    run Replica(0);
    run Replica(1);
    run Replica(2)
  }
  rnd = 0;
  do
  :: atomic {
     (done[0] && done[1] && done[2] && done[3]) || !go ->
     if
     :: go -> rnd++
     :: else -> go = 1
     fi;
     if
     :: rnd >= HORIZON -> go = 0; final_checks(); break
     :: else -> skip
     fi;
     /* P6: the voter never waits for ever: in TMR the next job it delivers is at most LATE_MAX
      * releases later than its vote was due */
     assert(!P_LATE || down[0] != 0 || restart[0] || !(v_mode == TMR || v_mode == STOPPING) ||
            rnd <= v_next_deliver + VOTE_LAG + LATE_MAX);
     /* P7: a switch (Starting or Stopping) ends within SWITCH_MAX releases */
     assert(!P_SWITCH || g_switch_since == 0 || rnd - g_switch_since <= SWITCH_MAX);
     done[0] = 0; done[1] = 0; done[2] = 0; done[3] = 0;
     /* the ground: filter_tmr at release 1; filter_simplex, or TMR again after a reported simplex */
     if
     :: rnd == 1 -> cmd_pending = 1; g_last_event = rnd
     :: else -> skip
     fi;
#if CMD_STOP
     if
     :: rnd > 1 && rnd <= FAULT_LAST && g_cmd_taken == 1 && v_mode == TMR -> cmd_pending = 2; g_last_event = rnd
     :: skip
     fi;
#endif
#if CMD_RETMR
     if
     :: rnd > 1 && rnd <= FAULT_LAST && g_cmd_taken == 1 && v_mode == SIMPLEX && g_simplex_reported &&
        down[0] == 0 -> cmd_pending = 1; g_last_event = rnd
     :: skip
     fi;
#endif
     /* the injector: at most MAXF faults, one a release, from FAULT_FIRST to FAULT_LAST */
     f = F_NONE;
     if
     :: nfaults < MAXF && rnd >= FAULT_FIRST && rnd <= FAULT_LAST ->
        if
        :: f = F_NONE
#ifndef NO_VOTER_FAULTS
        :: down[0] == 0 && (STOPPING_VOTER_FAULTS || v_mode != STOPPING) -> f = F_V_HANG; hang(0)
        :: down[0] == 0 && (STOPPING_VOTER_FAULTS || v_mode != STOPPING) -> f = F_V_RESET; crash(0)
#if MIDJOB
        :: down[0] == 0 && (STOPPING_VOTER_FAULTS || v_mode != STOPPING) -> f = F_V_MIDJOB; midjob_armed = 1
#endif
#if LATEJOB
        :: down[0] == 0 && (STOPPING_VOTER_FAULTS || v_mode != STOPPING) -> f = F_V_LATE; midjob_armed = 9
#endif
#endif
#ifndef NO_REPLICA_FAULTS
        :: p = 0; f = F_R_HANG
        :: p = 1; f = F_R_HANG
        :: p = 2; f = F_R_HANG
        :: p = 0; f = F_R_RESET
        :: p = 1; f = F_R_RESET
        :: p = 2; f = F_R_RESET
        :: p = 0; f = F_R_BADOUT
        :: p = 1; f = F_R_BADOUT
        :: p = 2; f = F_R_BADOUT
        :: p = 0; f = F_R_STATE
        :: p = 1; f = F_R_STATE
        :: p = 2; f = F_R_STATE
        :: p = 0; f = F_R_REFUSE
        :: p = 1; f = F_R_REFUSE
        :: p = 2; f = F_R_REFUSE
        :: p = 0; f = F_R_MIDJOB
        :: p = 1; f = F_R_MIDJOB
        :: p = 2; f = F_R_MIDJOB
#endif
        fi;
        if
        :: f == F_R_HANG -> if :: down[p + 1] == 0 -> hang(p + 1) :: else -> f = F_NONE fi
        :: f == F_R_RESET -> crash(p + 1)
        :: f == F_R_BADOUT -> pend_badout[p] = 1
        :: f == F_R_STATE -> pend_state[p] = 1
        :: f == F_R_REFUSE -> pend_state[p] = 2
        :: f == F_R_MIDJOB -> midjob_armed = 2 + p
        :: else -> skip
        fi;
        if
        :: f != F_NONE ->
           nfaults++; g_last_event = rnd;
           printf("MODEL fault round=%d kind=%d replica=%d\n", rnd, f, (f >= F_R_HANG && f != F_V_MIDJOB && f != F_V_LATE -> p : 255))
        :: else -> skip
        fi
     :: else -> skip
     fi;
     /* a hung or booting tile takes no step this release */
     p = 0;
     do
     :: p < 4 ->
        if
        :: down[p] > 0 -> down[p]--; done[p] = 1
        :: else -> skip
        fi;
        p++
     :: else -> break
     od
     }
  od
}

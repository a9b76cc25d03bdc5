{-# OPTIONS_GHC -O2 #-}
{-# LANGUAGE RankNTypes #-}

-- | The standard function blocks of "Stref.IEC.StandardFB" on the fast
-- evaluator's slots: each meaning as it is written there, step for step,
-- reading and writing the instance's variables where they lie instead of
-- in a map keyed by name. The definitions in "Stref.IEC.StandardFB" stay
-- the reference: test/IEC/FastStandardFBSpec.hs checks that each twin
-- leaves the variables the reference leaves, on random instances, inputs,
-- clocks and policies.
module Stref.IEC.Fast.StandardFB
  ( Twin (..)
  , twin
  , twinNames
  ) where

import Control.Monad.ST (ST)
import Data.Text (Text)
import qualified Data.Vector.Mutable as MV
import Stref.IEC.Checked (key)
import Stref.IEC.Fast.Operators (boolValue)
import Stref.IEC.StandardFB (downQ, libraryNames, pvMax, pvMin)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

-- | A standard FB's meaning on an instance: the clock (milliseconds), the
-- slots and where the instance starts in them.
data Twin = Twin !(forall s. Integer -> MV.MVector s Value -> Int -> ST s ())

-- | The FBs that have a twin, by key.
twinNames :: [Text]
twinNames = ["SR", "RS", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "TON", "TOF", "TP"]

-- | The twin of a standard FB under the policies, given the offset of each
-- of its variables in an instance (by key); Nothing for the FBs without
-- one (RTC and util.library's keep their instance in a map).
twin :: Policies -> Text -> (Text -> Maybe Int) -> Maybe Twin
twin pol name at = case key name of
  -- TC-FB-18: Q1 := S1 OR (NOT R AND Q1)
  "SR" -> do
    [s1, r, q1] <- mapM at [set1, reset, "Q1"]
    fb $ \_ i -> do
      q <- (||) <$> bool i s1 <*> ((&&) <$> (not <$> bool i r) <*> bool i q1)
      setB i q1 q
  -- TC-FB-17: Q1 := NOT R1 AND (S OR Q1)
  "RS" -> do
    [s, r1, q1] <- mapM at [set, reset1, "Q1"]
    fb $ \_ i -> do
      q <- (&&) <$> (not <$> bool i r1) <*> ((||) <$> bool i s <*> bool i q1)
      setB i q1 q
  -- TC-FB-16: Q := CLK AND NOT M; M := CLK
  "R_TRIG" -> do
    [clk, q, m] <- mapM at ["CLK", "Q", "$M"]
    fb $ \_ i -> do
      c <- bool i clk
      old <- bool i m
      setB i q (c && not old)
      setB i m c
  -- TC-FB-15: Q := NOT CLK AND NOT M; M := NOT CLK
  "F_TRIG" -> do
    [clk, q, m] <- mapM at ["CLK", "Q", "$M"]
    fb $ \_ i -> do
      c <- bool i clk
      old <- bool i m
      setB i q (not c && not old)
      setB i m (not c)
  -- TC-FB-22, TC-FB-23
  "CTU" -> do
    [cu, mcu, r, pv, q, cv] <- mapM at ["CU", "$CU", reset, "PV", "Q", "CV"]
    fb $ \_ i -> do
      up <- edge i cu mcu
      reset' <- bool i r
      n <- int i cv
      let n'
            | reset' = 0
            | up && n < pvMax counter = n + 1
            | otherwise = n
      limit <- int i pv
      setI i counter cv n'
      setB i q (n' >= limit)
  -- TC-FB-19, TC-FB-21
  "CTD" -> do
    [cd, mcd, ld, pv, q, cv] <- mapM at ["CD", "$CD", load, "PV", "Q", "CV"]
    fb $ \_ i -> do
      down <- edge i cd mcd
      load' <- bool i ld
      n <- int i cv
      preset <- int i pv
      let n'
            | load' = preset
            | down && n > pvMin counter = n - 1
            | otherwise = n
      setI i counter cv n'
      setB i q (downQ pol n')
  -- TC-FB-24..26
  "CTUD" -> do
    [cu, mcu, cd, mcd, r, ld, pv, qu, qd, cv] <- mapM at ["CU", "$CU", "CD", "$CD", reset, load, "PV", "QU", "QD", "CV"]
    fb $ \_ i -> do
      up <- edge i cu mcu
      down <- edge i cd mcd
      n <- int i cv
      reset' <- bool i r
      load' <- bool i ld
      preset <- int i pv
      let n'
            | reset' = 0
            | load' = preset
            | up && down = n
            | up && n < pvMax counter = n + 1
            | down && n > pvMin counter = n - 1
            | otherwise = n
      setI i counter cv n'
      setB i qu (n' >= preset)
      setB i qd (downQ pol n')
  -- TC-FB-27
  "TON" -> timer $ \now t@(input, pt, q, et, running, _, _, reached) i -> do
    on <- bool i input
    if not on
      then do
        setT i et 0
        setB i q False
        setB i running False
        setB i reached False
      else do
        elapsed <- started now t i
        limit <- int i pt
        before <- bool i reached
        let !hit = elapsed >= limit
        setT i et (min elapsed limit)
        setB i q $ case pTimerQ pol of
          SameCycle -> hit
          NextCycle -> hit && before
        setB i reached hit
  -- TC-FB-28, TC-ERRATA-8
  "TOF" -> timer $ \now t@(input, pt, q, et, running, _, _, _) i -> do
    on <- bool i input
    out <- bool i q
    if on
      then do
        setT i et 0
        setB i q True
        setB i running False
      else
        if out
          then do
            elapsed <- started now t i
            limit <- int i pt
            if elapsed >= limit
              then do
                setT i et limit
                setB i q False
                setB i running False
              else setT i et elapsed
          else pure ()
  -- TC-FB-29, TC-FB-30
  "TP" -> timer $ \now t@(input, pt, q, et, running, _, prev, _) i -> do
    on <- bool i input
    before <- bool i prev
    let !rising = on && not before
    setB i prev on
    limit <- int i pt
    run <- bool i running
    if run || rising
      then do
        elapsed <- started now t i
        if elapsed >= limit
          then do
            setT i et (if on then limit else 0)
            setB i q False
            setB i running False
          else do
            setT i et elapsed
            setB i q True
      else
        if on
          then pure ()
          else do
            setT i et 0
            setB i q False
  _ -> Nothing
  where
    (set1, reset, set, reset1, load, counter) = libraryNames pol
    fb :: (forall s. Integer -> Inst s -> ST s ()) -> Maybe Twin
    fb f = Just (Twin (\now v base -> f now (Inst v base)))
    timer :: (forall s. Integer -> TimerVars -> Inst s -> ST s ()) -> Maybe Twin
    timer f = do
      [input, pt, q, et, running, start, prev, reached] <- mapM at ["IN", "PT", "Q", "ET", "$RUN", "$START", "$PREV", "$REACHED"]
      fb (\now -> f now (input, pt, q, et, running, start, prev, reached))

-- | A timer's variables: IN, PT, Q, ET and its hidden $RUN, $START, $PREV,
-- $REACHED.
type TimerVars = (Int, Int, Int, Int, Int, Int, Int, Int)

-- | The time since the timer started, starting it now if it was not running.
started :: Integer -> TimerVars -> Inst s -> ST s Integer
started now (_, _, _, _, running, start, _, _) i = do
  run <- bool i running
  if run
    then pure ()
    else do
      setB i running True
      setT i start now
  s <- int i start
  pure $! now - s

-- | An instance's slots.
data Inst s = Inst !(MV.MVector s Value) !Int

-- | A rising edge of an input, with its memory (the R_TRIG inside the
-- counters).
edge :: Inst s -> Int -> Int -> ST s Bool
edge i input memory = do
  x <- bool i input
  m <- bool i memory
  setB i memory x
  pure $! x && not m

-- | The variables as the reference reads them: a BOOL (FALSE when it is
-- none), a number or a duration (0 when it is none).
bool :: Inst s -> Int -> ST s Bool
bool (Inst v b) o =
  MV.read v (b + o) >>= \case
    VBool x -> pure x
    _ -> pure False

int :: Inst s -> Int -> ST s Integer
int (Inst v b) o =
  MV.read v (b + o) >>= \case
    VInt _ n -> pure n
    VTime _ n -> pure n
    _ -> pure 0

setB :: Inst s -> Int -> Bool -> ST s ()
setB (Inst v b) o x = MV.write v (b + o) $! boolValue x

setI :: Inst s -> Elem -> Int -> Integer -> ST s ()
setI (Inst v b) e o n = MV.write v (b + o) $! VInt e n

setT :: Inst s -> Int -> Integer -> ST s ()
setT (Inst v b) o n = MV.write v (b + o) $! VTime TIME n

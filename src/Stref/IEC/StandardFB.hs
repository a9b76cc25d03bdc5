-- | The standard function blocks of Tab.3.22 (TC-FB-2..31): bistables, edge
-- detectors, counters and timers. Each is a meaning function from the
-- instance's variables (inputs already written) to its variables after the
-- call; timers read the virtual clock.
--
-- Hidden state (an edge memory, a timer's start) lives in variables whose
-- names start with @$@, which no program can name.
module Stref.IEC.StandardFB
  ( standardFBs
  , standardFBNames
  ) where

import qualified Data.Map.Strict as M
import Data.Text (Text)
import Stref.IEC.Checked
import Stref.IEC.Syntax (Pos (..), PouKind (..), Section (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

standardFBNames :: [Text]
standardFBNames = ["SR", "RS", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "TP", "TON", "TOF"]

-- | The standard FBs under the given policies (F_TRIG's initial memory is a
-- policy, TC-FB-15).
standardFBs :: Policies -> [(Text, PouDef)]
standardFBs pol =
  [ fb "SR" [inB set1, inB reset, outB "Q1"] [] (sr set1 reset) -- TC-FB-2, NX-FB-1
  , fb "RS" [inB set, inB reset1, outB "Q1"] [] (rs set reset1) -- TC-FB-3, NX-FB-4
  , fb "R_TRIG" [inB "CLK", outB "Q"] [("$M", VBool False)] rTrig -- TC-FB-4
  , fb "F_TRIG" [inB "CLK", outB "Q"] [("$M", VBool (pFTrigInitial pol == FTrigTrue))] fTrig -- TC-FB-5
  , fb "CTU" [inB "CU", inB reset, inC "PV", outB "Q", outC "CV"] [("$CU", VBool False)] (ctu counter reset) -- TC-FB-6, NX-FB-11
  , fb "CTD" [inB "CD", inB load, inC "PV", outB "Q", outC "CV"] [("$CD", VBool False)] (ctd counter load) -- TC-FB-7, NX-FB-14
  , fb "CTUD" [inB "CU", inB "CD", inB reset, inB load, inC "PV", outB "QU", outB "QD", outC "CV"] [("$CU", VBool False), ("$CD", VBool False)] (ctud counter reset load) -- TC-FB-8, NX-FB-17
  , fb "TP" [inB "IN", inT "PT", outB "Q", outT "ET"] timerState tp -- TC-FB-9
  , fb "TON" [inB "IN", inT "PT", outB "Q", outT "ET"] timerState ton -- TC-FB-10
  , fb "TOF" [inB "IN", inT "PT", outB "Q", outT "ET"] timerState tof -- TC-FB-11
  ]
  where
    fb n vars hidden meaning =
      let infos = [VarInfo v v s t (defaultValue t) False Nothing Nothing noP Volatile | (v, s, t) <- vars]
          hiddenInfos = [VarInfo h h SecVar (TElem BOOL) v False Nothing Nothing noP Volatile | (h, v) <- hidden]
          allVars = infos ++ hiddenInfos
       in (n, PouDef KFunctionBlock n allVars (M.fromList [(viKey v, v) | v <- allVars]) Nothing (Native meaning) noP Nothing True M.empty)
    noP = Pos 0 0
    -- the library's names and the counters' type (policy standard-library)
    (set1, reset, set, reset1, load, counter) = case pStandardLibrary pol of
      LibraryIec -> ("S1", "R", "S", "R1", "LD", INT) -- TC-FB-13: PV and CV are INT
      LibraryCodesys -> ("SET1", "RESET", "SET", "RESET1", "LOAD", WORD) -- NX-FB-11: WORD
    inB n = (n, SecInput, TElem BOOL)
    outB n = (n, SecOutput, TElem BOOL)
    inC n = (n, SecInput, TElem counter)
    outC n = (n, SecOutput, TElem counter)
    inT n = (n, SecInput, TElem TIME)
    outT n = (n, SecOutput, TElem TIME)
    timerState = [("$RUN", VBool False), ("$START", VTime TIME 0), ("$PREV", VBool False), ("$REACHED", VBool False)]
    tp = timerTP
    ton = timerTON
    tof = timerTOF

bool :: Text -> FBState -> Bool
bool k s = case M.lookup k s of
  Just (VBool b) -> b
  _ -> False

int :: Text -> FBState -> Integer
int k s = case M.lookup k s of
  Just (VInt _ n) -> n
  Just (VTime _ n) -> n
  _ -> 0

setB :: Text -> Bool -> FBState -> FBState
setB k = M.insert k . VBool

setI :: Elem -> Text -> Integer -> FBState -> FBState
setI e k = M.insert k . VInt e

setT :: Text -> Integer -> FBState -> FBState
setT k = M.insert k . VTime TIME

-- | TC-FB-18, NX-FB-2: @Q1 := S1 OR (NOT R AND Q1)@ (set dominant).
sr :: Text -> Text -> StandardFB
sr set1 reset _ _ s = setB "Q1" (bool set1 s || (not (bool reset s) && bool "Q1" s)) s

-- | TC-FB-17, NX-FB-5: @Q1 := NOT R1 AND (S OR Q1)@ (reset dominant).
rs :: Text -> Text -> StandardFB
rs set reset1 _ _ s = setB "Q1" (not (bool reset1 s) && (bool set s || bool "Q1" s)) s

-- | TC-FB-16: @Q := CLK AND NOT M; M := CLK@.
rTrig :: StandardFB
rTrig _ _ s = setB "$M" (bool "CLK" s) (setB "Q" (bool "CLK" s && not (bool "$M" s)) s)

-- | TC-FB-15: @Q := NOT CLK AND NOT M; M := NOT CLK@, M's initial value by
-- policy @f-trig-initial@.
fTrig :: StandardFB
fTrig _ _ s = setB "$M" (not (bool "CLK" s)) (setB "Q" (not (bool "CLK" s) && not (bool "$M" s)) s)

-- | A rising edge of an input, with its memory (the R_TRIG inside the
-- counters).
edge :: Text -> Text -> FBState -> (Bool, FBState)
edge input memory s = (bool input s && not (bool memory s), setB memory (bool input s) s)

-- | The counters count within their type: IEC's PVmax and PVmin for INT
-- (TC-FB-21, TC-FB-23), 0 and 65535 for WORD.
pvMax, pvMin :: Elem -> Integer
pvMax = snd . intRange
pvMin = fst . intRange

-- | The down counters' Q (TC-FB-19, TC-FB-20, policy @down-counter-q@).
downQ :: Policies -> Integer -> Bool
downQ pol cv = case pDownCounterQ pol of
  EqualZero -> cv == 0
  AtMostZero -> cv <= 0

-- | TC-FB-22: R clears CV; a rising edge of CU adds one (not past the
-- type's maximum, TC-FB-23); Q := CV >= PV.
ctu :: Elem -> Text -> StandardFB
ctu e reset _ _ s0 =
  let (up, s1) = edge "CU" "$CU" s0
      cv
        | bool reset s1 = 0
        | up && int "CV" s1 < pvMax e = int "CV" s1 + 1
        | otherwise = int "CV" s1
   in setB "Q" (cv >= int "PV" s1) (setI e "CV" cv s1)

-- | TC-FB-19: LD loads PV; a rising edge of CD subtracts one (not below the
-- type's minimum, TC-FB-21); Q per @down-counter-q@.
ctd :: Elem -> Text -> StandardFB
ctd e load pol _ s0 =
  let (down, s1) = edge "CD" "$CD" s0
      cv
        | bool load s1 = int "PV" s1
        | down && int "CV" s1 > pvMin e = int "CV" s1 - 1
        | otherwise = int "CV" s1
   in setB "Q" (downQ pol cv) (setI e "CV" cv s1)

-- | TC-FB-24: R clears, else LD loads, else one edge counts (both edges at
-- once change nothing: TC-FB-25, TC-FB-26); QU := CV >= PV; QD per policy.
ctud :: Elem -> Text -> Text -> StandardFB
ctud e reset load pol _ s0 =
  let (up, s1) = edge "CU" "$CU" s0
      (down, s2) = edge "CD" "$CD" s1
      cv0 = int "CV" s2
      cv
        | bool reset s2 = 0
        | bool load s2 = int "PV" s2
        | up && down = cv0
        | up && cv0 < pvMax e = cv0 + 1
        | down && cv0 > pvMin e = cv0 - 1
        | otherwise = cv0
   in setB "QD" (downQ pol cv) (setB "QU" (cv >= int "PV" s2) (setI e "CV" cv s2))

-- | TC-FB-27: while IN is TRUE, ET counts the time since IN rose, up to PT;
-- Q once it reached PT (in that call, or under @timer-q = next-cycle@ in
-- the next); IN FALSE clears Q and ET.
timerTON :: StandardFB
timerTON pol now s
  | not (bool "IN" s) = setB "$REACHED" False (setB "$RUN" False (setB "Q" False (setT "ET" 0 s)))
  | otherwise =
      let s1 = if bool "$RUN" s then s else setT "$START" now (setB "$RUN" True s)
          elapsed = now - int "$START" s1
          pt = int "PT" s1
          reached = elapsed >= pt
          q = case pTimerQ pol of
            SameCycle -> reached
            NextCycle -> reached && bool "$REACHED" s1
       in setB "$REACHED" reached (setB "Q" q (setT "ET" (min elapsed pt) s1))

-- | TC-FB-28 read as IEC's off-delay (TC-ERRATA-8): Q is TRUE while IN is
-- TRUE and for PT after IN falls; ET counts from the fall up to PT.
timerTOF :: StandardFB
timerTOF _ now s
  | bool "IN" s = setB "$RUN" False (setB "Q" True (setT "ET" 0 s))
  | bool "Q" s =
      let s1 = if bool "$RUN" s then s else setT "$START" now (setB "$RUN" True s)
          elapsed = now - int "$START" s1
          pt = int "PT" s1
       in if elapsed >= pt
            then setB "$RUN" False (setB "Q" False (setT "ET" pt s1))
            else setT "ET" elapsed s1
  | otherwise = s

-- | TC-FB-29: a rising edge of IN starts a pulse of length PT (not
-- retriggered while it lasts); ET counts up to PT and returns to 0 once
-- IN is FALSE after the pulse (TC-FB-30).
timerTP :: StandardFB
timerTP _ now s0 =
  let rising = bool "IN" s0 && not (bool "$PREV" s0)
      s = setB "$PREV" (bool "IN" s0) s0
      pt = int "PT" s
   in if bool "$RUN" s || rising
        then
          let s1 = if bool "$RUN" s then s else setT "$START" now (setB "$RUN" True s)
              elapsed = now - int "$START" s1
           in if elapsed >= pt
                then setB "$RUN" False (setB "Q" False (setT "ET" (if bool "IN" s1 then pt else 0) s1))
                else setB "Q" True (setT "ET" elapsed s1)
        else if bool "IN" s then s else setT "ET" 0 (setB "Q" False s)

-- | The standard function blocks of Tab.3.22 (TC-FB-2..31): bistables, edge
-- detectors, counters and timers. Each is a meaning function from the
-- instance's variables (inputs already written) to its variables after the
-- call; timers read the virtual clock.
--
-- Under @standard-library = codesys@ also standard.library's RTC
-- (NX-FB-30..32) and the function blocks of util.library the Nexto manual
-- documents with their behaviour (UNPACK, HYSTERESIS, LIMITALARM,
-- LIN_TRAFO, CHARCURVE: NX-FB-37..40), with util.library's structure POINT
-- ('libraryTypes').
--
-- Hidden state (an edge memory, a timer's start) lives in variables whose
-- names start with @$@, which no program can name.
module Stref.IEC.StandardFB
  ( standardFBs
  , standardFBNames
  , libraryTypes
  , libraryNames
  , pvMax
  , pvMin
  , downQ
  ) where

import qualified Data.Map.Strict as M
import Data.Foldable (toList)
import Data.Bits (testBit)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.IEC.Checked
import Stref.IEC.Syntax (Pos (..), PouKind (..), Section (..), TypeDecl (..), TypeSpec (..), VarDecl (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

standardFBNames :: [Text]
standardFBNames = ["SR", "RS", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "TP", "TON", "TOF"]

-- | The standard FBs under the given policies (F_TRIG's initial memory is a
-- policy, TC-FB-15; the library is policy @standard-library@).
standardFBs :: Policies -> [(Text, PouDef)]
standardFBs pol =
  iecFBs pol ++ case pStandardLibrary pol of
    LibraryIec -> []
    LibraryCodesys -> codesysFBs

-- | The types util.library declares, as a declaration would write them,
-- under @standard-library = codesys@: POINT, a structure of two INTs X and
-- Y, the points of CHARCURVE (L14160-14165).
libraryTypes :: Policies -> [TypeDecl]
libraryTypes pol = case pStandardLibrary pol of
  LibraryIec -> []
  LibraryCodesys -> [TypeDecl noPos "POINT" (TSStruct noPos [VarDecl noPos [(noPos, "X"), (noPos, "Y")] Nothing (TSName noPos "INT") Nothing Nothing [] []]) Nothing []]

-- | POINT as the checker resolves the declaration of 'libraryTypes'.
pointType :: Type
pointType = TStruct "POINT" [("X", TElem INT), ("Y", TElem INT)]

noPos :: Pos
noPos = Pos 0 0

-- | A native FB: its declared variables (name, section, type), its hidden
-- ones (name, type, initial value) and its meaning.
nativeFB :: Text -> [(Text, Section, Type)] -> [(Text, Type, Value)] -> StandardFB -> (Text, PouDef)
nativeFB n vars hidden meaning =
  let infos = [VarInfo v v s t (defaultValue t) False Nothing Nothing noPos Volatile | (v, s, t) <- vars]
      hiddenInfos = [VarInfo h h SecVar t v False Nothing Nothing noPos Volatile | (h, t, v) <- hidden]
      allVars = infos ++ hiddenInfos
   in (n, PouDef KFunctionBlock n allVars (M.fromList [(viKey v, v) | v <- allVars]) Nothing (Native meaning) noPos Nothing [] M.empty True M.empty)

iecFBs :: Policies -> [(Text, PouDef)]
iecFBs pol =
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
    fb n vars hidden = nativeFB n vars [(h, TElem BOOL, v) | (h, v) <- hidden]
    (set1, reset, set, reset1, load, counter) = libraryNames pol
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

-- | The names of the bistables' and counters' inputs and the counters'
-- type, by policy @standard-library@: S1, R, S, R1, LD and INT (TC-FB-13),
-- or SET1, RESET, SET, RESET1, LOAD and WORD (NX-FB-11).
libraryNames :: Policies -> (Text, Text, Text, Text, Text, Elem)
libraryNames pol = case pStandardLibrary pol of
  LibraryIec -> ("S1", "R", "S", "R1", "LD", INT)
  LibraryCodesys -> ("SET1", "RESET", "SET", "RESET1", "LOAD", WORD)

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

------------------------------------------------------------------------
-- CODESYS: standard.library's RTC and util.library (standard-library =
-- codesys)

codesysFBs :: [(Text, PouDef)]
codesysFBs =
  [ nativeFB "RTC" [inp "EN" BOOL, inp "PDT" DT, out "Q" BOOL, out "CDT" DT] [("$EN", TElem BOOL, VBool False), ("$START", TElem LINT, VInt LINT 0), ("$BASE", TElem DT, VDT 0)] rtc -- NX-FB-30
  , nativeFB "UNPACK" (inp "B" BYTE : [out (bitName i) BOOL | i <- [0 .. 7]]) [] unpack -- NX-FB-37
  , nativeFB "HYSTERESIS" [inp "IN" INT, inp "HIGH" INT, inp "LOW" INT, out "OUT" BOOL] [] hysteresis -- NX-FB-39
  , nativeFB "LIMITALARM" [inp "IN" INT, inp "HIGH" INT, inp "LOW" INT, out "O" BOOL, out "U" BOOL, out "IL" BOOL] [] limitAlarm -- NX-FB-40
  , nativeFB "LIN_TRAFO" [inp "IN" REAL, inp "IN_MIN" REAL, inp "IN_MAX" REAL, inp "OUT_MIN" REAL, inp "OUT_MAX" REAL, out "OUT" REAL, out "ERROR" BOOL] [] linTrafo -- NX-FB-38
  , nativeFB "CHARCURVE" [inp "IN" INT, inp "N" BYTE, ("P", SecInput, TArray [(0, 10)] pointType), out "OUT" INT, out "ERR" BYTE] [] charCurve -- NX-FB-38
  ]
  where
    inp n e = (n, SecInput, TElem e)
    out n e = (n, SecOutput, TElem e)

bitName :: Int -> Text
bitName i = "B" <> T.pack (show i)

-- | NX-FB-30..32 (L13501-13546): while EN is FALSE, Q is FALSE and CDT is
-- DT#1970-01-01-00:00:00; on EN's rising edge CDT takes PDT and from then
-- on counts the whole seconds the clock advanced since that edge; Q is TRUE
-- while EN is (CDT "is incrementing"). Decision: PDT is read at the edge
-- only.
rtc :: StandardFB
rtc _ now s
  | not (bool "EN" s) = setB "$EN" False (setB "Q" False (M.insert "CDT" (VDT 0) s))
  | otherwise =
      let s1
            | bool "$EN" s = s
            | otherwise = M.insert "$BASE" (M.findWithDefault (VDT 0) "PDT" s) (setI LINT "$START" now (setB "$EN" True s))
          base = case M.lookup "$BASE" s1 of
            Just (VDT ms) -> ms
            _ -> 0
          seconds = (now - int "$START" s1) `div` 1000
       in setB "Q" True (M.insert "CDT" (VDT (base + seconds * 1000)) s1)

-- | NX-FB-37 (L13655-13660): the bits of the BYTE B in B0 (bit 0) .. B7.
unpack :: StandardFB
unpack _ _ s = foldr (\i -> setB (bitName i) (testBit (int "B" s) i)) s [0 .. 7]

-- | NX-FB-39 (L14246-14260): OUT becomes TRUE when IN is below LOW and
-- FALSE when IN exceeds HIGH; otherwise (IN = LOW, IN = HIGH, in between)
-- it keeps its value.
hysteresis :: StandardFB
hysteresis _ _ s
  | int "IN" s < int "LOW" s = setB "OUT" True s
  | int "IN" s > int "HIGH" s = setB "OUT" False s
  | otherwise = s

-- | NX-FB-40 (L14266-14278): O when IN exceeds HIGH, U when IN is below
-- LOW, IL otherwise (IN between the limits, both included). Decision: with
-- LOW above HIGH an IN beyond both is O (the first test wins).
limitAlarm :: StandardFB
limitAlarm _ _ s =
  let x = int "IN" s
      o = x > int "HIGH" s
      u = not o && x < int "LOW" s
   in setB "IL" (not o && not u) (setB "U" u (setB "O" o s))

-- | NX-FB-38 (L13710-13745): OUT lies in OUT_MIN..OUT_MAX as IN lies in
-- IN_MIN..IN_MAX, @(IN - IN_MIN) * (OUT_MAX - OUT_MIN) / (IN_MAX - IN_MIN) +
-- OUT_MIN@ in REAL (each operation rounded to binary32). ERROR when IN_MIN
-- = IN_MAX or IN is below IN_MIN or above IN_MAX. Decision: with ERROR, OUT
-- keeps its value (the manual does not say what it holds).
linTrafo :: StandardFB
linTrafo _ _ s
  | lo == hi || x < lo || x > hi = setB "ERROR" True s
  | otherwise = setB "ERROR" False (M.insert "OUT" (VReal ((x - lo) * (ohi - olo) / (hi - lo) + olo)) s)
  where
    real k = case M.lookup k s of
      Just (VReal r) -> r
      _ -> 0
    x = real "IN"
    lo = real "IN_MIN"
    hi = real "IN_MAX"
    olo = real "OUT_MIN"
    ohi = real "OUT_MAX"

-- | NX-FB-38 (L14155-14203): the curve through the points P[0]..P[N-1],
-- read at IN. ERR 4 when N is not within 2..11; else ERR 1 when the points'
-- X do not increase; else ERR 2 and the nearer end point's Y when IN lies
-- before P[0].X or beyond P[N-1].X; else ERR 0 and the line between the
-- two points around IN. Decisions: X must increase strictly (a segment of
-- width 0 has no slope); the line is @Y0 + (IN - X0) * (Y1 - Y0) / (X1 -
-- X0)@ computed exactly, the division truncating toward zero, the result
-- kept in INT by its low bits; with ERR 4 or 1 OUT keeps its value.
charCurve :: StandardFB
charCurve _ _ s
  | n < 2 || n > 11 = err 4 s
  | or (zipWith (>=) xs (drop 1 xs)) = err 1 s
  | x < head xs = err 2 (outI (head ys))
  | x > last xs = err 2 (outI (last ys))
  | otherwise = err 0 (outI (line (zip pts (drop 1 pts))))
  where
    n = int "N" s
    x = int "IN" s
    pts = take (fromInteger n) points
    xs = map fst pts
    ys = map snd pts
    points = case M.lookup "P" s of
      Just (VArray _ vs) -> [(field "X" v, field "Y" v) | v <- toList vs]
      _ -> []
    field k = \case
      VStruct fs | Just (VInt _ v) <- M.lookup k fs -> v
      _ -> 0
    err e = setI BYTE "ERR" e
    outI v = setI INT "OUT" (wrapInt INT v) s
    line segs = case [seg | seg@(_, (x1, _)) <- segs, x <= x1] of
      ((x0, y0), (x1, y1)) : _ -> y0 + ((x - x0) * (y1 - y0)) `quot` (x1 - x0)
      [] -> last ys

-- | The fast IEC evaluator (Stref.IEC.Fast) against the readable one
-- (Stref.IEC.Eval.runCycle, the definition): wherever the fast one accepts
-- a program, every scan cycle gives the same machine and the same stop
-- (position and fault), on the corpus cases of the IEC dialects and on
-- generated programs. Each cycle starts both from the machine the readable
-- evaluator left, so that a difference is seen at the cycle that makes it.
-- The expected values are the readable evaluator's, never the fast one's.
module IEC.FastSpec (spec) where

import Control.Exception (evaluate)
import Control.Monad (foldM)
import qualified Data.Map.Strict as M
import Data.Maybe (isJust)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Case (Case (..), IecSetup (..), effectiveExpect)
import Stref.Conformance.Corpus (Corpus (..), Entry (..), loadCorpus)
import Stref.Conformance.Protocol
import Stref.Conformance.Runner (buildRequest, casePolicies, defaultRunOptions)
import Stref.Generate.Iec
import Stref.IEC.Check (ProgramChoice (..), checkUnit)
import Stref.IEC.Checked (Program)
import Stref.IEC.Engine
import Stref.IEC.Eval
import Stref.IEC.Fast (fastCycle, fastCycleOnly)
import Stref.IEC.Parser (parseUnit)
import Stref.Policy
import System.Timeout (timeout)
import Test.Hspec
import Test.QuickCheck

-- | The checked program, or Nothing when the source is rejected.
checked :: Policies -> ProgramChoice -> Text -> Maybe Program
checked pol choice src = either (const Nothing) Just (parseUnit pol "fast.st" src >>= checkUnit pol choice)

-- | A run as the engine makes it (initialisation, the variables written
-- before each cycle, resets), with each cycle computed by both evaluators:
-- the cycles where they differ, and how many cycles the fast one ran
-- itself (not handing them to the readable one) of how many. Nothing when
-- the fast evaluator does not accept the program.
differences :: Policies -> Program -> Integer -> [(Text, Scalar)] -> [Call] -> Maybe ([String], (Int, Int))
differences pol prog cycle initial calls = do
  fast <- fastCycle pol prog
  only <- fastCycleOnly pol prog
  let (started, initError) = initialize pol prog Nothing (initialMachine prog)
      go _ _ [] = ([], (0, 0))
      go m k (Reset ev : rest) = go (fst (restart pol prog ev m)) k rest
      go m k (Scan sets : rest) = case foldM (setPath pol prog) m sets of
        Left _ -> ([], (0, 0))
        Right m1 ->
          let clock = toInteger (k - 1) * cycle
              readable@(m2, stop) = runCycle pol prog clock m1
              other = fast clock m1
              -- compared as shown: a NaN equals itself there, and -0.0 is not 0.0
              here = ["cycle " <> show k <> ": readable " <> show stop <> ", fast " <> show (snd other) <> describe m2 (fst other) | show readable /= show other]
              ran = if isJust (only clock m1) then 1 else 0
              (later, (n, total)) = case stop of
                Just _ | pAfterError pol == StopController -> ([], (0, 0))
                _ -> go m2 (k + 1) rest
           in (here ++ later, (ran + n, 1 + total))
  pure $ case (initError, foldM (setPath pol prog) started initial) of
    (Nothing, Right m0) -> go m0 (1 :: Int) calls
    _ -> ([], (0, 0))
  where
    describe a b = concat [" (" <> what <> " differ)" | (what, f) <- [("globals", show . mGlobals), ("programs", show . mPrograms), ("frames", show . mFrames), ("steps", show . mSteps), ("memory", show . mMemory)], f a /= f b]

-- | A corpus case as the engine runs it (Stref.IEC.Engine.iecAnswer):
-- Nothing when outside the fast evaluator's slice.
caseDifferences :: Case -> Maybe ([String], (Int, Int))
caseDifferences c = do
  (pol, rq, _, cycle, prog, calls) <- caseRun c
  differences pol prog cycle (M.toList (prInit (rqPlc rq))) calls

-- | What the engine needs to run a corpus case of an IEC dialect: the
-- policies, the request, the program choice, the cycle, the checked
-- program and the calls. Nothing for another case or a rejected program.
caseRun :: Case -> Maybe (Policies, Request, ProgramChoice, Integer, Program, [Call])
caseRun c = do
  pol <- either (const Nothing) Just (casePolicies defaultRunOptions c)
  _ <- caseIec c
  let rq = buildRequest pol c (effectiveExpect pol c)
      choice = maybe ProgramsOfConfiguration ProgramNamed (rqProgram rq)
  cycle <- either (const Nothing) Just (cycleMillis pol (maybe "T#10ms" id (rqCycle rq)))
  prog <- checked pol choice (rqSource rq)
  calls <- mapM callOf (rqCalls rq)
  Just (pol, rq, choice, cycle, prog, calls)
  where
    callOf cr = case callReset cr of
      Nothing -> Just (Scan (M.toList (callSet cr)))
      Just r -> Reset <$> lookup r resetEvents

-- | A corpus case run whole by the engine with the fast evaluator where it
-- applies (which runs consecutive cycles as one batch on its slots) and
-- with the readable one: where they differ (the machine after the run, the
-- first error with its cycle, the cycles run). Nothing when the fast
-- evaluator does not accept the program.
runDifference :: Case -> Maybe (Maybe String)
runDifference c = do
  (pol, rq, choice, cycle, prog, calls) <- caseRun c
  _ <- fastCycle pol prog
  let run ev = case runProgramWith ev Nothing Nothing pol "fast.st" (rqSource rq) choice cycle (M.toList (prInit (rqPlc rq))) calls of
        Right (Right (r, _)) -> Right (show (rrMachine r), show (rrError r), rrCycles r)
        Right (Left e) -> Left (show e)
        Left _ -> Left "rejected"
      (readable, fast) = (run Readable, run FastWhereItApplies)
  pure (if readable == fast then Nothing else Just (T.unpack (caseId c) <> ": readable " <> show readable <> ", fast " <> show fast))

-- | A generated program over its cycles.
generatedDifferences :: Policies -> GenProgram -> Maybe [String]
generatedDifferences pol gp = do
  prog <- checked pol ProgramsOfConfiguration (renderProgram gp)
  fst <$> differences pol prog 10 [] (replicate (gpCalls gp) (Scan []))

-- | The generated programs the fast evaluator accepts agree with the readable one.
agreeOn :: Policies -> Gen GenProgram -> Property
agreeOn pol gen = withMaxSuccess 250 . forAll gen $ \gp ->
  case generatedDifferences pol gp of
    Nothing -> label "outside the slice" True
    Just ds -> label "on the fast path" (counterexample (T.unpack (renderProgram gp) <> unlines ds) (null ds))

spec :: Spec
spec = describe "IEC.Fast: the fast evaluator gives the readable evaluator's cycles" $ do
  it "on every corpus case of tecomat and nexto it accepts, cycle by cycle (and it accepts at least 1095 of them)" $ do
    corpus <- loadCorpus ["conformance/tecomat", "conformance/nexto"]
    let cases = [c | Loaded c <- corpusEntries corpus]
        results = [(caseId c, r) | c <- cases, Just r <- [caseDifferences c]]
        failing = [(i, take 1 ds) | (i, (ds, _)) <- results, not (null ds)]
        (ran, cycles) = foldl (\(a, b) (_, (_, (x, y))) -> (a + x, b + y)) (0, 0) results
        running = length [() | c <- cases, Right pol <- [casePolicies defaultRunOptions c], Just setup <- [caseIec c], Just _ <- [checked pol (maybe ProgramsOfConfiguration ProgramNamed (iecProgram setup)) (caseSource c)]]
    putStrLn ("      the fast path runs " <> show (length results) <> " of the " <> show running <> " corpus cases whose program the checker accepts (" <> show (length cases) <> " cases); " <> show ran <> " of their " <> show cycles <> " cycles without handing one to the readable evaluator")
    failing `shouldBe` []
    length results `shouldSatisfy` (>= 1095)
  it "on every corpus case of tecomat and nexto it accepts, run whole by the engine (cycles in batches on its slots)" $ do
    corpus <- loadCorpus ["conformance/tecomat", "conformance/nexto"]
    [d | Loaded c <- corpusEntries corpus, Just (Just d) <- [runDifference c]] `shouldBe` []
  it "on generated tecomat programs" $
    agreeOn tecomat (genProgram fullSupport)
  it "on generated nexto programs (pointers and methods among them)" $
    agreeOn nexto (genProgram codesysSupport)
  -- the closures on Int decide by the policies where a result leaves its
  -- type, a divisor is zero or an index its bounds: the other alternatives
  it "on generated tecomat programs under the other alternatives of the policies the Int closures decide on" $
    conjoin
      [ agreeOn pol (genProgram fullSupport)
      | pol <-
          [ tecomat {pOverflow = Saturate, pModSign = ModSignEuclidean, pShortCircuit = ShortCircuit, pForBounds = ForOnce, pIndexOutOfRange = IndexClamp}
          , tecomat {pOverflow = Trap, pTimeRange = TimeUnsigned, pForAtTypeMax = StopAtEnd, pIndexOutOfRange = IndexTrap}
          ]
      ]
  -- an index is translated once (the closures on Int beside the ones on
  -- values): a translation that doubled at each level would not end here
  it "translates an index nested 45 deep in linear time, and runs it on the fast path" $ do
    let nested = iterate (\x -> "table[" <> x <> "]") "start" !! 45
        src = T.unlines ["PROGRAM MAIN", "VAR", "  table : ARRAY [0..9] OF INT := [1, 2, 3, 4, 5, 6, 7, 8, 9, 0];", "  start : INT;", "  result : INT;", "END_VAR", "result := " <> nested <> ";", "END_PROGRAM"]
        Just prog = checked tecomat ProgramsOfConfiguration src
    ran <- timeout 30000000 (evaluate (differences tecomat prog 10 [] [Scan []]) >>= \d -> length (show d) `seq` pure d)
    ran `shouldBe` Just (Just ([], (1, 1)))
  -- the control paths the closures take as functions of their own (a FOR
  -- at the end of its type, EXIT and CONTINUE in REPEAT and WHILE, a
  -- backward JMP to a one-statement label, an FB call whose instance index
  -- and input could both fault): the fast path runs each cycle itself and
  -- leaves what the readable evaluator leaves
  describe "runs loops, jumps and calls that end early as the readable evaluator does" $
    mapM_ ending
      [ ("a FOR that ends at its type's maximum", tecomat, ["idx : INT;", "count : DINT;"], ["FOR idx := 32760 TO 32767 DO", "  count := count + 1;", "END_FOR;"])
      , ("CONTINUE and EXIT in REPEAT, EXIT in WHILE", nexto, ["idx : INT;", "odd : INT;"], ["idx := 0;", "REPEAT", "  idx := idx + 1;", "  IF idx MOD 2 = 0 THEN CONTINUE; END_IF;", "  odd := odd + 1;", "  IF idx > 50 THEN EXIT; END_IF;", "UNTIL idx >= 100", "END_REPEAT;", "WHILE idx > 0 DO", "  idx := idx - 7;", "  IF idx < 20 THEN EXIT; END_IF;", "END_WHILE;"])
      , ("a backward JMP to a label", nexto, ["idx : INT;"], ["idx := 0;", "again:", "idx := idx + 1;", "IF idx < 10 THEN JMP again; END_IF;"])
      , ("an FB call with its instance's index out of range and an input out of its subrange", tecomat, ["units : ARRAY [0..1] OF Limited;", "which : INT := 5;", "big : SINT := 100;"], ["units[which](level := big);"])
      ]
  -- what makes the benchmarks of issue #23 fast: each cycle of theirs runs
  -- on the fast path, none handed to the readable evaluator
  describe "runs the IEC benchmarks of bench/programs on the fast path, and agrees on their first cycles" $
    mapM_ benchmark [("fbscan", tecomat), ("strings", tecomat), ("lreal", nexto), ("oop", nexto), ("pointers", nexto)]
  where
    ending (what, pol, vars, body) = it what $ do
      let limited = ["FUNCTION_BLOCK Limited", "VAR_INPUT", "  level : SINT(0..10);", "END_VAR", "VAR_OUTPUT", "  seen : SINT;", "END_VAR", "seen := level;", "END_FUNCTION_BLOCK"]
          src = T.unlines (limited ++ ["PROGRAM MAIN", "VAR"] ++ vars ++ ["END_VAR"] ++ body ++ ["END_PROGRAM"])
          Just prog = checked pol ProgramsOfConfiguration src
      differences pol prog 10 [] (replicate 2 (Scan [])) `shouldSatisfy` \case
        Just ([], (ran, total)) -> ran == total && total >= 1
        _ -> False
    benchmark (name, pol) = it name $ do
      src <- TIO.readFile ("bench/programs/" <> name <> ".st")
      let Just prog = checked pol ProgramsOfConfiguration src
      differences pol prog 10 [] (replicate 3 (Scan [])) `shouldBe` Just ([], (3, 3))

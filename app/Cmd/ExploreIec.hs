-- | @stref explore --dialect tecomat@: generated IEC programs
-- ("Stref.Generate.Iec"), run over a few cycles; disagreements between the
-- alternatives of a policy (@--compare@) or between the reference and an
-- engine (@--engine@) are shrunk to a small program and printed with the
-- variables that differ.
module Cmd.ExploreIec
  ( ExploreIec (..)
  , IecMode (..)
  , exploreIec
  ) where

import Control.Monad (forM_)
import Data.IORef
import Data.Scientific (floatingOrInteger)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import System.Exit
import System.IO (hFlush, stdout)
import Stref.Conformance.Protocol
import Stref.Conformance.Runner (EngineSpec (..), RunOptions (..), askEngine, defaultRunOptions)
import Stref.Generate.Iec
import Stref.IEC.Check (ProgramChoice (..))
import Stref.IEC.Engine
import Stref.IEC.Eval (Stop (..), readVariablePath)
import Stref.IEC.Values (Fault (..))
import Stref.Policy
import Stref.Verification (VerificationError (..))
import Test.QuickCheck.Gen (unGen)
import Test.QuickCheck.Random (mkQCGen)

data IecMode = IecCompare Text | IecEngine String | IecPrint

data ExploreIec = ExploreIec
  { eiMode :: IecMode
  , eiDialect :: Text -- ^ the dialect the requests name
  , eiSupport :: Support -- ^ what the programs may use (all, less what the engine lacks)
  , eiCount :: Int
  , eiSeed :: Int
  , eiSize :: Int
  , eiShrinkBudget :: Int
  , eiTimeout :: Double
  }

-- | What a run shows: the variables (as protocol values) and the error kind.
data Seen = Seen (M.Map Text Scalar) (Maybe Text) | SeenRejected Text | SeenOther Text
  deriving (Eq, Show)

generated :: Support -> Int -> Int -> GenProgram
generated su size s = unGen (genProgram su) (mkQCGen s) size

reference :: Policies -> GenProgram -> Seen
reference pol gp = case runProgram pol "explore.st" (renderProgram gp) ProgramsOfConfiguration 10 [] (replicate (gpCalls gp) (Scan [])) of
  Left e -> SeenRejected (veKind e <> ": " <> veMessage e)
  Right (Left e) -> SeenOther e
  Right (Right r) ->
    Seen
      (M.fromList [(p, programScalar (rrProgram r) v) | p <- observedPaths (gpSupport gp), Right steps <- [parseVarPath p], Just (v, _) <- [readVariablePath (rrProgram r) (rrMachine r) steps]])
      ((\(_, StopFault _ f) -> faultKind f) <$> rrError r)

-- | The differences between two results: variable, left, right.
differences :: Policies -> GenProgram -> Seen -> Seen -> [(Text, Text, Text)]
differences pol gp a b = case (a, b) of
  (Seen va ea, Seen vb eb) ->
    let types = observedTypes pol (renderProgram gp) Nothing (observedPaths (gpSupport gp))
        same k x y = maybe (x == y) (\t -> scalarsMatch pol t x y) (M.lookup k types)
     in [(k, shown x, shown y) | (k, x) <- M.toList va, Just y <- [M.lookup k vb], not (same k x y)]
          ++ [("error", maybe "none" id ea, maybe "none" id eb) | ea /= eb]
  _ | a == b -> []
    | otherwise -> [("outcome", outcome a, outcome b)]
  where
    outcome = \case
      Seen _ e -> maybe "ran" ("runtime error " <>) e
      SeenRejected m -> "rejected (" <> T.strip m <> ")"
      SeenOther m -> m
    shown = \case
      SNumber n -> either (T.pack . show) (T.pack . show) (floatingOrInteger n :: Either Double Integer)
      SBool x -> if x then "TRUE" else "FALSE"
      SText t -> t
      s -> T.pack (show s)

exploreIec :: Policies -> ExploreIec -> IO ExitCode
exploreIec pol o = do
  putStrLn ("seed " <> show (eiSeed o) <> " (replay with --seed " <> show (eiSeed o) <> " --count " <> show (eiCount o) <> " --size " <> show (eiSize o) <> ")")
  forM_ (supportSummary (supportUnder pol) (eiSupport o)) $ \s -> TIO.putStrLn ("the programs use only " <> s)
  let progs = [(s, generated (eiSupport o) (eiSize o) s) | s <- take (eiCount o) [eiSeed o ..]]
  case eiMode o of
    IecPrint -> do
      forM_ progs $ \(s, gp) -> do
        putStrLn ("(* program " <> show s <> ", " <> show (gpCalls gp) <> " cycles *)")
        TIO.putStr (renderProgram gp)
        putStrLn ("(* " <> show (reference pol gp) <> " *)")
      pure ExitSuccess
    IecCompare name -> case alternativesOf name pol of
      Left msg -> TIO.putStrLn ("stref explore: " <> msg) >> pure (ExitFailure 2)
      Right alts -> do
        let disagree gp = case [reference p gp | (_, p) <- alts] of
              (first : rest) -> any (\x -> not (null (differences pol gp first x))) rest
              [] -> False
        search progs disagree $ \small -> do
          let results = [(a, reference p small) | (a, p) <- alts]
          case results of
            ((a0, r0) : rest) -> forM_ rest $ \(a, r) -> forM_ (differences pol small r0 r) $ \(k, x, y) ->
              TIO.putStrLn ("  " <> k <> ": " <> name <> "=" <> a0 <> " gives " <> x <> ", " <> name <> "=" <> a <> " gives " <> y)
            [] -> pure ()
    IecEngine cmd -> do
      let ropts = defaultRunOptions {roEngine = External cmd, roTimeout = eiTimeout o}
          request gp =
            Request protocolVersion "explore" (eiDialect o) (M.fromList (policyAssignments pol)) (renderProgram gp) "P"
              (PlcRequest (Declare M.empty M.empty) "" M.empty Nothing)
              (replicate (gpCalls gp) (CallRequest (True, True, True) M.empty Nothing))
              (Observe [] (observedPaths (gpSupport gp)) [] True) Nothing (Just "T#10ms")
          engineSeen gp = do
            a <- askEngine ropts (request gp)
            pure $ case a of
              Right (AnswerRun _ ob) -> Seen (obVars ob) (obError ob >>= erKind)
              Right (AnswerRejected _ k m) -> SeenRejected (maybe "" id k <> ": " <> m)
              Right (AnswerUnsupported r) -> SeenOther ("unsupported: " <> r)
              Left e -> SeenOther ("engine-error: " <> e)
      cache <- newIORef M.empty
      let seenOf gp = do
            c <- readIORef cache
            case M.lookup (renderProgram gp) c of
              Just x -> pure x
              Nothing -> do
                x <- engineSeen gp
                modifyIORef cache (M.insert (renderProgram gp) x)
                pure x
      -- the pure search needs the engine's answers first: ask for each program
      results <- mapM (\(s, gp) -> (s,gp,) <$> seenOf gp) progs
      -- a program the engine does not compile (its language is narrower:
      -- MATIEC wants a statement in every loop body) or declines is
      -- counted, not a disagreement: the corpus shows such differences,
      -- explore looks for different results
      let declined = [s | (s, gp, e) <- results, isRejection e, not (isRejection (reference pol gp))]
          isRejection = \case
            SeenRejected _ -> True
            SeenOther m -> "unsupported" `T.isPrefixOf` m
            _ -> False
          bad = [(s, gp) | (s, gp, e) <- results, s `notElem` declined, not (null (differences pol gp (reference pol gp) e))]
          declinedNote = if null declined then "" else " (" <> show (length declined) <> " rejected or declined by the engine)"
      case bad of
        [] -> putStrLn ("no disagreement in " <> show (length progs) <> " programs" <> declinedNote) >> pure ExitSuccess
        ((s, gp) : _) -> do
          putStrLn ("program " <> show s <> ": the engine disagrees with the reference; shrinking ...")
          -- a shrink step keeps the kind of disagreement: values that differ
          -- must not turn into a program one side rejects
          first <- seenOf gp
          let kind r e = case (r, e) of
                (Seen {}, Seen {}) -> "values"
                _ -> T.pack (show (outcomeKind r, outcomeKind e))
              outcomeKind = \case
                Seen {} -> 0 :: Int
                SeenRejected _ -> 1
                SeenOther _ -> 2
              wanted = kind (reference pol gp) first
          small <- shrinkIO (eiShrinkBudget o) (\c -> (\e -> kind (reference pol c) e == wanted && not (null (differences pol c (reference pol c) e))) <$> seenOf c) gp
          TIO.putStr (renderCompact small)
          e <- seenOf small
          forM_ (differences pol small (reference pol small) e) $ \(k, x, y) ->
            TIO.putStrLn ("  " <> k <> ": reference " <> x <> ", engine " <> y)
          pure (ExitFailure 1)
  where
    search progs disagree report = case [(s, gp) | (s, gp) <- progs, disagree gp] of
      [] -> putStrLn ("no disagreement in " <> show (length progs) <> " programs") >> pure ExitSuccess
      ((s, gp) : _) -> do
        putStrLn ("program " <> show s <> " shows the difference; shrinking ...")
        hFlush stdout
        small <- shrinkIO (eiShrinkBudget o) (pure . disagree) gp
        TIO.putStr (renderCompact small)
        _ <- report small
        pure (ExitFailure 1)

-- | Greedy shrinking within a budget of runs.
shrinkIO :: Int -> (GenProgram -> IO Bool) -> GenProgram -> IO GenProgram
shrinkIO budget bad = go budget
  where
    go b gp = do
      r <- first b (shrinkProgram gp)
      case r of
        (Just gp', b') -> go b' gp'
        (Nothing, _) -> pure gp
    first b [] = pure (Nothing, b)
    first b (c : cs)
      | b <= 0 = pure (Nothing, 0)
      | otherwise = bad c >>= \x -> if x then pure (Just c, b - 1) else first (b - 1) cs
